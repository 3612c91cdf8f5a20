"""The recognition service survives every case of issue 12: each is answered with one
error line (exit 2 in file mode), and the next request is still recognized."""

import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from recognizer.curves import Pose
from recognizer.limits import MAX_SAMPLES_PER_TOUCH, MAX_TOUCHES
from tools.bench_recognizer import exact_request
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
GOOD = exact_request("ellipse", {"a": 28.6, "b": 17.3}, [0.36, 1.86, 4.23], Pose(0.3, 120.0, 15.0), False)
T = GOOD["touches"]
C = T[0]["contact"]
SLOW = exact_request("ellipse", {"a": 28.6, "b": 17.3}, np.linspace(0.1, 6.0, 64), Pose(0.3, 120.0, 15.0), False)

CASES = [
    (b'{"scene":{"classes":[["circle"]]},"touches":[]}', "unknown class"),
    (json.dumps({"scene": {"classes": ["circle"], "object": {"class": "circle", "params": {"r": 1}}},
                 "touches": T}).replace('"r": 1', '"r": 100000000000000000000').encode(), "21 digits"),
    (json.dumps({"scene": "a" * 5000, "touches": T}).encode(), "path of 5000 characters"),
    (json.dumps({"scene": "/dev/zero", "touches": T}).encode(), "not a regular file"),
    (json.dumps({"touches": [{"phi": list(range(MAX_SAMPLES_PER_TOUCH + 1)), "x": [0] * 501, "y": [0] * 501}] * 2}
                ).encode(), "501 samples (at most 500"),
    (json.dumps({"touches": [{"contact": dict(C, x=i)} for i in range(MAX_TOUCHES + 1)]}).encode(), "65 touches"),
    (b'{"touches": [], "meta": "\xff\xfe"}', "not valid UTF-8"),
    (json.dumps(GOOD).replace(f'"x": {C["x"]}', '"x": 1' + "0" * 400, 1).encode(), "401 digits"),
    (json.dumps(GOOD).replace(f'"x": {C["x"]}', '"x": 1' + "0" * 5000, 1).encode(), "5001 digits"),
    (json.dumps({"touches": [T[0], {"contact": dict(T[1]["contact"], kappa=1e200)}, T[2]]}).encode(), "kappa: |1e+200|"),
    (json.dumps({"touches": [T[0], {"contact": dict(T[1]["contact"], kappa_s=-1e30)}, T[2]]}).encode(), "kappa_s"),
    (json.dumps({"touches": [dict(T[0], contact=dict(C, x=1e7))] + T[1:]}).encode(), "beyond 1e+06 mm"),
    (b'{"touches": [' + b"0," * 1_100_000 + b"0]}", "longer than 2097152 bytes"),
    (b"[" * 20000 + b"]" * 20000, "nested deeper than 32"),
    (json.dumps({**SLOW, "options": {"timeout_s": 0.01}}).encode(), "cut off after 0.01 s"),
    (json.dumps({**GOOD, "options": {"timeout_s": 0}}).encode(), "timeout_s: must be in (0, 3600]"),
]


def test_stream_survives_every_issue_case(monkeypatch, capsys):
    data = b"".join(raw + b"\n" + json.dumps(GOOD).encode() + b"\n" for raw, _ in CASES)
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    assert main(["recognize", "--stream", "-"]) == 0
    out = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    assert len(out) == 2 * len(CASES)
    for (_, msg), bad, good in zip(CASES, out[::2], out[1::2]):
        assert msg in bad.get("error", ""), (msg, bad)
        assert good["class"] == "ellipse"


@pytest.mark.parametrize("raw,msg", [CASES[0], CASES[6], CASES[7], CASES[8], CASES[9], CASES[14]])
def test_file_mode_exit_2_one_line(tmp_path, raw, msg):
    p = tmp_path / "r.json"
    p.write_bytes(raw)
    r = subprocess.run([sys.executable, "-m", "tools.cli", "recognize", str(p)], capture_output=True, cwd=ROOT,
                       timeout=120, env={"PYTHONPATH": str(ROOT), "LC_ALL": "C.UTF-8", "PYTHONIOENCODING": "utf-8:strict"})
    err = r.stderr.decode()
    assert r.returncode == 2 and r.stdout == b"" and err.count("\n") == 1 and msg in err, err


def test_kappa_far_but_within_limits_is_inconsistent_not_ignored(capsys, tmp_path):
    """Absurd is not exact: a κ a thousand times the others' is rejected by the χ² tests."""
    p = tmp_path / "r.json"
    p.write_text(json.dumps({"touches": [T[0], {"contact": dict(T[1]["contact"], kappa=1e3)}, T[2]]}))
    assert main(["recognize", str(p)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["class"] == "unclassified" and not any(r["consistent"] for r in out["ranking"])


def test_sharp_but_real_curvature_is_accepted(capsys, tmp_path):
    """The limit leaves room for the sharpest curve recognized exactly (ellipse 1:1000)."""
    p = tmp_path / "r.json"
    p.write_text(json.dumps(exact_request("ellipse", {"a": 1e3, "b": 1.0}, [0.0, 0.4, 1.5707963267948966, 2.5],
                                          Pose(2.0, 110.0, -5.0), False)))
    assert main(["recognize", str(p)]) == 0
    assert json.loads(capsys.readouterr().out)["class"] == "ellipse"
