"""Audit: which refusals of a bench's runs name no move (a benchmark helper, not a test).

Reads run logs (``tactile demo/explore --log``; the ``randN.log`` files ``tools.bench_explore``
writes beside its scenes) and, for every run that ended refused, says what the refusal asks of
a person, as ``tactile demo`` prints it (tools.cmd_explore.refusal): the move of the object its
stop names (the log's ``stopped_early``/``budget_spent`` event, tactile_jaw.choose.Stop), or
else another action it names — a finer jaw (tactile_jaw.decide.FINER), a profile with more
touches, or none: no class fits (no move is known to help then, tactile_jaw.choose.budget_advice)
—, or nothing a person can act on beyond "move or turn the object": those are listed as naming
no move (issue 20: every refusal names its move). The true class comes from the scene file
beside the log, when there is one. Run: ``python -m tools.refusal_audit DIR_OR_LOG ...``
(``--all`` lists every refusal, not only those naming no move).
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

#: what a refusal names when it names no move (:func:`named`), in the order they are looked for
NAMED = (("a move", None), ("finer angles", "a jaw with >="), ("more touches", "--profile accurate"),
         ("no class fits", "no class of the scene fits"), ("a placement", "no pad reaches"))


def named(answer: dict) -> str:
    """What a refusal's answer (tools.cmd_explore.refusal) names for a person to do: 'a move' when
    its stop names one, else the first of ``NAMED`` its reason or advice says, else 'no move'.
    'a placement' is a search that found no move within its limits (tactile_jaw.choose.move_advice)."""
    if answer.get("move") is not None:
        return "a move"
    text = f"{answer.get('reason') or ''} {answer.get('advice') or ''}"
    return next((what for what, words in NAMED[1:] if words in text), "no move")


def audit_log(path: Path) -> dict | None:
    """The refusal of one run log (its class, what it names, its advice), or None when the run
    answered a class (or never reached its result)."""
    from hand_driver.log import read_log
    import yaml
    from tactile_jaw.choose import last_stop
    from tactile_jaw.decide import refusal_kind
    from tools.cmd_explore import refusal

    contents = read_log(str(path))
    result = contents.result
    if result is None:
        return None
    rec = result.get("recognition")
    if rec is not None and rec.get("class") != "unclassified":
        return None
    stop = last_stop(contents.events)
    answer = refusal(rec, None if rec is not None else
                     f"{result.get('touches_used', 0)} of {result.get('touches_tried', 0)} touches usable",
                     stop, contents.jaw_config())
    scene = path.with_suffix(".yaml")
    truth = None
    if scene.is_file():
        obj = (yaml.safe_load(scene.read_text()) or {}).get("object") or {}
        truth = obj.get("class")
    return {"log": str(path), "truth": truth, "named": named(answer),
            "kind": refusal_kind(answer.get("reason") or answer["advice"], answer.get("move")),
            "advice": answer["advice"]}


def _logs(paths: list[str]) -> list[Path]:
    out = []
    for p in map(Path, paths):
        out += sorted(p.glob("*.log"), key=_natural) if p.is_dir() else [p]
    return out


def _natural(p: Path):
    return [int(s) if s.isdigit() else s for s in re.split(r"(\d+)", p.name)]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("paths", nargs="+", help="run logs, or directories of them (*.log)")
    ap.add_argument("--all", action="store_true", help="list every refusal, not only those naming no move")
    args = ap.parse_args(argv)
    rows = [r for r in map(audit_log, _logs(args.paths)) if r is not None]
    print("| log | true class | names | kind | advice |")
    print("|---|---|---|---|---|")
    for r in rows:
        if args.all or r["named"] in ("no move", "a placement"):
            print(f"| {r['log']} | {r['truth'] or '?'} | {r['named']} | {r['kind']} | {r['advice'][:240]} |")
    counts = {what: sum(r["named"] == what for r in rows) for what, _ in NAMED + (("no move", None),)}
    print(f"\n{len(rows)} refusals: " + ", ".join(f"{n} name {what}" for what, n in counts.items() if n))
    return 0


if __name__ == "__main__":
    sys.exit(main())
