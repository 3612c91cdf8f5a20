"""Numbers in the docs that cannot go stale: ``python -m tools.docs_figures`` reruns
``tactile demo`` on every example scene and rewrites, between their markers, the blocks of
the docs that quote those runs:

- ``<!-- figures:demo -->`` in README.md and docs/exploration.md: what ``tactile demo``
  prints on the default scene (tests/test_docs_figures.py fails when it differs, robot time
  included: the emulator runs in lockstep; only the wall time is not compared);
- ``<!-- figures:results -->`` in README.md: the results table's example-scene answer and
  robot-time cells;
- ``<!-- figures:examples -->`` in docs/exploration.md: the example scenes' table (answer,
  error, touches, robot time and where it went);
- ``<!-- figures:log -->`` in docs/formats.md: lines of the default scene's run log.

``--check`` rewrites nothing and exits 1 when a block would change. The runs take ~2 min
of CPU, two at a time (``--jobs``). Run it after any change to the recognizer, the jaw
pipeline or the exploration, and commit what it rewrote.
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"
EXPLORATION = REPO / "docs" / "exploration.md"
FORMATS = REPO / "docs" / "formats.md"
#: the example scenes, in the order of the README's results table (the default scene, an ellipse, too)
SCENES = ("default", "line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola")
#: what a block's lines may differ in between two runs of the same code (wall time is the host's)
WALL_TIME = re.compile(r"wall time [0-9.]+ s")


@dataclass
class Run:
    """One ``tactile demo --scene config/scenes/<scene>.yaml --log L`` run."""

    scene: str
    status: int
    lines: list[str]  # stdout, without the log: line
    result: dict  # the log's result record
    log_lines: list[str]

    def line(self, prefix: str) -> str:
        return next((ln[len(prefix):].strip() for ln in self.lines if ln.startswith(prefix)), "")


def run_demo(scene: str, workdir: Path) -> Run:
    log = workdir / f"{scene}.jsonl"
    proc = subprocess.run([sys.executable, "-m", "tools.cli", "demo", "--scene", f"config/scenes/{scene}.yaml",
                           "--log", str(log)], cwd=REPO, capture_output=True, text=True, timeout=1800)
    if proc.returncode not in (0, 3):
        raise SystemExit(f"tactile demo --scene {scene}: exit {proc.returncode}: {proc.stderr.strip()[-500:]}")
    log_lines = log.read_text().splitlines()
    # the result record: the last but for the log's documented tail (a fault event, end)
    result = next(rec for rec in map(json.loads, reversed(log_lines)) if rec["type"] == "result")
    lines = [ln for ln in proc.stdout.splitlines() if not ln.startswith("log: ")]
    return Run(scene, proc.returncode, lines, result, log_lines)


def demo_block(run: Run) -> str:
    return "```\n" + "\n".join(run.lines) + "\n```"


def _answer_cell(run: Run) -> str:
    """The answer as the results table gives it: class and errors, or the refusal's why."""
    if run.status == 0:
        error = run.line("error:").replace("no parameters; ", "")
        return f"{run.result['recognition']['class']}, {error}"
    reason = run.line("refused:")
    why = re.sub(r"^not decisive after \d+ usable touches: ", "", reason).split("; ")[0]
    return "refused: " + (why if len(why) <= 140 else why[:137].rsplit(" ", 1)[0] + " …")


def _robot_time(run: Run) -> str:
    return f"{run.result['robot_time_s']:.1f} s"


def results_rows(runs: dict[str, Run]) -> dict[str, tuple[str, str]]:
    """README results table: class row → (answer cell, robot time cell)."""
    rows = {}
    for scene in SCENES[1:]:
        answer, time_s = _answer_cell(runs[scene]), _robot_time(runs[scene])
        if scene == "ellipse":
            answer += f" (default scene: {runs['default'].line('error:').split(';')[0]})"
            time_s += f", default {_robot_time(runs['default'])}"
        rows[scene.replace("_", " ")] = (answer, time_s)
    return rows


def results_table(table: str, runs: dict[str, Run]) -> str:
    """The README's results table with its example-scene cells (columns 4 and 5) rewritten."""
    rows = results_rows(runs)
    out = []
    for line in table.splitlines():
        cells = line.split(" | ")
        name = cells[0].lstrip("| ").strip()
        if name in rows and len(cells) >= 6:
            cells[3], cells[4] = rows[name]
        out.append(" | ".join(cells))
    return "\n".join(out)


def examples_table(runs: dict[str, Run]) -> str:
    head = ("| scene | answer | touches used/tried | robot time | probes (transits) | touches (transits) | retreat |\n"
            "|---|---|---|---|---|---|---|")
    rows = []
    for scene in SCENES:
        r = runs[scene]
        t = r.result["time_s"]
        rows.append(f"| `{scene}` | {_answer_cell(r)} | {r.result['touches_used']}/{r.result['touches_tried']} | "
                    f"{_robot_time(r)} | {t['probes']:.1f} s ({t['probe_transits']:.1f}) | "
                    f"{t['touches']:.1f} s ({t['touch_transits']:.1f}) | {t['retreat']:.1f} s |")
    return "\n".join([head, *rows])


def log_excerpt(run: Run) -> str:
    """The default run's log: the header (config, scene, versions and command shortened to
    "…"), its first record of every other kind, the result (answer shortened) and the tail
    after it (the ``end`` record); every hash but the last shortened to "…"."""
    records = [json.loads(ln) for ln in run.log_lines]
    last = max(i for i, rec in enumerate(records) if rec["type"] == "result")
    header = {**records[0], **{k: "…" for k in ("config", "scene", "versions", "command")}}
    picked, seen = [header], set()
    for rec in records[1:last]:
        kind = (rec["type"], rec.get("kind"))
        if kind not in seen:
            seen.add(kind)
            if rec.get("kind") == "touch_used":
                rec = {**rec, "samples": "…"}
            picked.append(rec)
    result = dict(records[last])
    rec = result.get("recognition")
    if rec:
        result["recognition"] = {k: rec[k] for k in ("class", "params", "pose")} | {"…": "…"}
    picked += [result, *records[last + 1:]]
    picked = [{**r, "h": "…"} if "h" in r else r for r in picked[:-1]] + picked[-1:]
    return "```json\n" + "\n".join(json.dumps(r, separators=(",", ":"), ensure_ascii=False) for r in picked) + "\n```"


def replace_block(text: str, name: str, content: str, path: Path) -> str:
    start, end = f"<!-- figures:{name}:start -->", f"<!-- figures:{name}:end -->"
    if text.count(start) != 1 or text.count(end) != 1:
        raise SystemExit(f"{path}: expected one {start} … {end} block")
    head, rest = text.split(start)
    _, tail = rest.split(end)
    return f"{head}{start}\n{content}\n{end}{tail}"


def block(text: str, name: str) -> str:
    """The content of a figures block (between its markers)."""
    start, end = f"<!-- figures:{name}:start -->", f"<!-- figures:{name}:end -->"
    return text.split(start)[1].split(end)[0].strip("\n")


def rewrite(runs: dict[str, Run]) -> dict[Path, str]:
    readme = README.read_text()
    readme = replace_block(readme, "demo", demo_block(runs["default"]), README)
    readme = replace_block(readme, "results", results_table(block(readme, "results"), runs), README)
    exploration = EXPLORATION.read_text()
    exploration = replace_block(exploration, "demo", demo_block(runs["default"]), EXPLORATION)
    exploration = replace_block(exploration, "examples", examples_table(runs), EXPLORATION)
    formats = replace_block(FORMATS.read_text(), "log", log_excerpt(runs["default"]), FORMATS)
    return {README: readme, EXPLORATION: exploration, FORMATS: formats}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m tools.docs_figures", description=__doc__.split("\n\n")[0])
    parser.add_argument("--jobs", type=int, default=2, help="demo runs at a time (default 2)")
    parser.add_argument("--check", action="store_true", help="rewrite nothing; exit 1 if a block would change")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(max(1, args.jobs)) as pool:
        runs = dict(zip(SCENES, pool.map(lambda s: run_demo(s, Path(tmp)), SCENES)))
    stale = []
    for path, text in rewrite(runs).items():
        old = path.read_text()
        if WALL_TIME.sub("wall time", old) != WALL_TIME.sub("wall time", text):
            stale.append(path.relative_to(REPO).as_posix())
        if not args.check:
            path.write_text(text)
    verb = "stale" if args.check else "rewritten"
    print(f"{verb}: {', '.join(stale) or 'none'}")
    return 1 if args.check and stale else 0


if __name__ == "__main__":
    raise SystemExit(main())
