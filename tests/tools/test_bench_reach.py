"""`bench_reach` on an object whose curved part the pads reach at one place only prints a row
that says so, not a traceback: random finite cubical 21 of `bench_explore --finite 4 --seed 191`
(P-series jaw), whose reachable roll centres span −76 … −75° of pad normal, one distinct place,
where its classes need two (recognizer.touches.check_touch_count)."""

from __future__ import annotations

import yaml

from tools import bench_reach

SCENE = {
    "classes": ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola"],
    "name": "rand21",
    "object": {
        "class": "cubical_parabola",
        "closure": [[1.7460991946883189, -17.46099194688319], [-20.953190336259826, -17.46099194688319]],
        "extent": [-20.953190336259826, 1.7460991946883189],
        "params": {"a": 0.0010495718017393162, "c": -0.5},
        "pose": {"theta": 0.5362685777876406, "x": 112.3054177260003, "y": 31.892028089784176},
    },
}


def test_one_reachable_place_is_a_row_not_a_traceback(tmp_path, capsys):
    scene = tmp_path / "rand21.yaml"
    scene.write_text(yaml.safe_dump(SCENE))
    assert bench_reach.main([str(scene), "--config", "config/jaw-p.yaml", "--touches", "5"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert "roll centres -76.0 ... -75.0 deg" in out[0]
    assert out[-1] == "| 1 | — | — | — | no: exploration: 1 touch(es); the scene's classes need at least 2 |"
