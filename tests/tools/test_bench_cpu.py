"""tools.bench_cpu: its requests are bench_wide's, and --compare tells identical answers from
changed ones (class, text, numbers beyond the tolerance)."""

from __future__ import annotations

import json

import numpy as np

from tools import bench_cpu
from tools.bench_wide import drawn_trial


def _write(path, answers):
    records = [{"name": f"line/{i}", "cpu_ms": 10.0, "next_touch_ms": None, "answer": a} for i, a in enumerate(answers)]
    path.write_text(json.dumps({"records": records}))
    return str(path)


def test_requests_are_bench_wides_first_recognitions():
    (name, (req, _)), = list(bench_cpu.requests(5, 1, 3, "wide", False, ["ellipse"]))
    touches = drawn_trial("ellipse", 3, 5, "wide").touches
    assert name == "ellipse/3" and len(req.touches) == len(touches)
    assert all(np.array_equal(a.x, b.x) and np.array_equal(a.phi, b.phi) for a, b in zip(req.touches, touches))


def test_compare_identical_and_changed(tmp_path, capsys):
    a = {"class": "circle", "params": {"r": 10.0}, "uncertainty": {"r": 0.1}, "reason": None}
    same = _write(tmp_path / "a.json", [a, a])
    assert bench_cpu.main(["--compare", same, same]) == 0
    assert "2 bit-identical" in capsys.readouterr().out
    tiny = _write(tmp_path / "b.json", [a, {**a, "params": {"r": 10.0 * (1 + 1e-12)}}])
    assert bench_cpu.main(["--compare", same, tiny]) == 0  # within the default 1e-9
    assert bench_cpu.main(["--compare", same, tiny, "--rel", "1e-13"]) == 1
    other = _write(tmp_path / "c.json", [a, {**a, "class": "ellipse"}])
    assert bench_cpu.main(["--compare", same, other]) == 1
    assert "DIFF line/1.class" in capsys.readouterr().out
