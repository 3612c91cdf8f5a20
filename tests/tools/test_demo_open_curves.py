"""`tactile demo` on open curves: the parabola scene ends with a reasoned refusal (its arms
offer the pads' faces less than one rolling touch of pad normal), a scene whose object
crosses the opened jaw is refused up front; never a traceback or a wrong class."""

from __future__ import annotations

import contextlib
import io
import json

from hand_driver.log import read_log
from tools.cli import main


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def test_parabola_scene_ends_with_a_reasoned_refusal(tmp_path):
    log = tmp_path / "parabola.jsonl"
    rc, out, err = _run(["demo", "--scene", "config/scenes/parabola.yaml", "--json", "--log", str(log)])
    assert "Traceback" not in err
    if rc == 0:  # a recognition, if the explorer ever gets one here, must be the right class
        assert json.loads(out)["class"] in ("parabola", "unclassified")
        return
    assert rc == 1
    assert "probes" in err.splitlines()[-1] and "too few to recognize" in err.splitlines()[-1]
    assert "probe 1:" in err  # the boundary was searched from several directions
    assert "no untouched pad orientation left" in err  # and the planner said why it stopped
    contents = read_log(log)
    assert len(contents.touches) >= 6  # probes of both fingers are in the log


def test_object_crossing_the_opened_jaw_is_refused_in_one_line():
    # the cubical parabola's S-curve crosses both pads of the opened jaw (y = +-45 mm)
    rc, out, err = _run(["demo", "--scene", "config/scenes/cubics.yaml"])
    assert rc == 2 and out == ""
    assert "Traceback" not in err
    assert "cubics.yaml: the object overlaps the opened jaw" in err.strip().splitlines()[-1]
