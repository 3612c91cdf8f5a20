"""A flat press that bulged once is pressed again before another pad's face is answered
`line` (tactile_jaw.flat_phase._bulge_pending). The hyperbola example on a P-series jaw of
another geometry (links 90 / 60 mm, 44 mm pads, bases 70 mm apart): every roll fell on a
corner or a pad end; in the flat phase the left pad's first press, on the curved part,
stopped +0.23 mm short of its supports (one bulge: perhaps rounding), its second was
stopped by the right pad's seat on the closing segment, the left pad dropped (it had no
face), and the right pad's three presses were answered `line` — a wrong class. Now the
left pad presses again, unstopped: a second bulge, a curved part, and the exploration
refuses ("closing segments, not a line")."""

from __future__ import annotations

import yaml

from hand_driver.log import read_log
from tactile_jaw.flat import bulged
from tactile_jaw.pipeline import logged_felt
from tactile_jaw.settings import ExploreSettings


def _other_geometry(path) -> str:
    raw = yaml.safe_load(open("config/jaw-p.yaml"))
    for finger, y in zip(raw["fingers"], (35.0, -35.0)):
        finger["base"]["y"] = y
        finger["joints"][0]["link_mm"], finger["joints"][1]["link_mm"] = 90.0, 60.0
        finger["pad"]["length_mm"] = 44.0
    path.write_text(yaml.safe_dump(raw))
    return str(path)


def test_a_single_bulge_is_confirmed_before_the_other_face_is_a_line(tmp_path, demo_answer):
    config = _other_geometry(tmp_path / "jaw-p-other.yaml")
    scene = yaml.safe_load(open("config/scenes/hyperbola.yaml"))
    log = tmp_path / "hyperbola.jsonl"
    answer = demo_answer(scene, tmp_path / "hyperbola.yaml", log, config=config)
    assert answer["class"] == "unclassified", answer["class"]
    assert "closing segments, not a line" in answer["reason"]
    contents = read_log(log)
    _, felt = logged_felt(contents.config, contents, ExploreSettings.from_profile("balanced"))
    assert sum(t.touch.finger == "left" and bulged(t) for t in felt) == 2
