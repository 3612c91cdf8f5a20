"""tools.refusal_audit: the refusals of a bench's run logs that name no move, and what the others name."""

from pathlib import Path

import yaml

from hand_driver.log import RunLog
from tools.refusal_audit import audit_log, main, named

ROOT = Path(__file__).resolve().parents[2]
REFUSED = {"class": "unclassified", "params": {}, "pose": None, "contacts": [], "invariants": {}, "uncertainty": {},
           "reason": "not decisive after 4 usable touches: …", "next_touch": None, "ranking": []}
MOVE = {"dx": -20.0, "dy": 4.0, "turn_deg": 30.0, "about": [130.0, 9.0]}


def _log(path: Path, recognition: dict | None, stop: dict | None, truth: str = "parabola") -> Path:
    config = yaml.safe_load((ROOT / "config" / "jaw-p.yaml").read_text())
    with RunLog(path).open(config=config, scene=None) as log:
        if stop is not None:
            log.write({"type": "event", **stop})
        log.write({"type": "result", "recognition": recognition, "robot_time_s": 18.0,
                   "touches_used": 0 if recognition is None else 4, "touches_tried": 6})
    path.with_suffix(".yaml").write_text(yaml.safe_dump({"object": {"class": truth}}))
    return path


def test_the_audit_lists_refusals_naming_no_move_and_says_what_the_others_name(tmp_path, capsys):
    moved = _log(tmp_path / "rand72.log", REFUSED, {"kind": "stopped_early", "message": "…: turn the object 30 deg",
                                                     "move": MOVE})
    ends = _log(tmp_path / "rand62.log", REFUSED, {"kind": "stopped_early", "message": "… (the object ends there): "
                                                   "move or turn the object so that more of its curved part faces "
                                                   "a finger"})
    none = _log(tmp_path / "rand2.log", None, None, "line")
    fits = _log(tmp_path / "rand105.log", {**REFUSED, "reason": "no class of the scene fits: closest …"},
                {"kind": "budget_spent", "message": "the touch budget of 8 is spent and no class of the scene fits the "
                                                    "touches: no move of the object is known to help"},
                "cubical_parabola")
    right = _log(tmp_path / "rand64.log", {**REFUSED, "class": "parabola", "params": {"a": 8.4}}, None)
    assert audit_log(right) is None
    rows = {p.stem: audit_log(p) for p in (moved, ends, none, fits)}
    assert {k: r["named"] for k, r in rows.items()} == {"rand72": "a move", "rand62": "no move", "rand2": "no move",
                                                         "rand105": "no class fits"}
    assert rows["rand72"]["kind"] == "out of reach" and rows["rand2"]["truth"] == "line"
    assert "place the object in the workspace disk" in rows["rand2"]["advice"]  # tactile demo's own advice
    assert main([str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "rand62.log" in out and "rand2.log" in out and "rand72.log" not in out and "rand105.log" not in out
    assert "4 refusals: 1 name a move, 1 name no class fits, 2 name no move" in out


def test_what_a_refusal_names_besides_a_move():
    assert named({"move": None, "advice": "…; a jaw with >= 262,144 ticks per turn tells them apart"}) == "finer angles"
    assert named({"move": None, "advice": "…: a profile with more touches (--profile accurate) may decide"}) == \
        "more touches"
    assert named({"move": None, "advice": "no pad reaches across its vertex … with the object moved up to 20 mm"}) == \
        "a placement"
    assert named({"move": MOVE, "advice": "a jaw with >= 1 ticks"}) == "a move"
