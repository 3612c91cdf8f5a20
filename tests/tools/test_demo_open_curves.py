"""`tactile demo` on open curves: the finite parabola example explored end to end (the
finger facing its flat bottom touches corners and the closing segment, which are rejected
with the reason; the other finger's touches on the curved part are recognized; the answer
is the parabola, its parameter within 2 %: the emulated jaw is deterministic); a scene
whose object crosses the opened jaw is refused up front."""

from __future__ import annotations

import json

from hand_driver.log import read_log


def test_finite_parabola_explored_end_to_end(tmp_path, tactile_in_process):
    log = tmp_path / "parabola.jsonl"
    rc, out, err = tactile_in_process(["demo", "--scene", "config/scenes/parabola.yaml", "--json", "--log", str(log)])
    assert "Traceback" not in err and rc == 0
    answer = json.loads(out)
    assert answer["class"] == "parabola", answer.get("reason")
    assert abs(answer["params"]["a"] / 8.0 - 1.0) < 0.02
    events = read_log(log).events
    rejected = [e["message"] for e in events if e.get("kind") == "touch_rejected"]
    off_curve = [m for m in rejected if m.split(": ", 1)[1].startswith(("corner:", "off the curved part"))]
    assert off_curve and all(m.startswith("right:") for m in off_curve)  # the flat bottom's side
    used = [e for e in events if e.get("kind") == "touch_used"]
    assert len(used) >= 3 and all(e["samples"]["finger"] == "left" for e in used)
    assert any(e.get("kind") == "finger_retired" for e in events)


def test_object_crossing_the_opened_jaw_is_refused_in_one_line(tactile_in_process):
    # the cubical parabola's S-curve crosses both pads of the opened jaw (y = +-45 mm)
    rc, out, err = tactile_in_process(["demo", "--scene", "config/scenes/cubics.yaml"])
    assert rc == 2 and out == ""
    assert "Traceback" not in err
    assert "cubics.yaml: the object overlaps the opened jaw" in err.strip().splitlines()[-1]
