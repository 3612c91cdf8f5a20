"""tactile recognize: file, stdin, --stream; bad input exits 2 with one line, no traceback."""

import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from recognizer.curves import Pose
from tactile_common.errors import InputError
from recognizer.touches import ContactTouch, SamplesTouch, parse_request
from tools.bench_recognizer import exact_request
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
GOOD = exact_request("ellipse", {"a": 28.6, "b": 17.3}, [0.36, 1.86, 4.23], Pose(0.3, 120.0, 15.0), False)


def test_file_answer_is_contract_json(tmp_path, capsys):
    p = tmp_path / "req.json"
    p.write_text(json.dumps({**GOOD, "scene": str(ROOT / "config/scenes/conics.yaml")}))
    assert main(["recognize", str(p)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= {"class", "params", "pose", "contacts", "invariants", "uncertainty", "reason"}
    assert out["class"] == "ellipse" and out["params"]["a"] == pytest.approx(28.6, rel=1e-9)
    assert out["pose"]["theta"] == pytest.approx(0.3) and len(out["contacts"]) == 3
    assert out["contacts"][0]["t"] == pytest.approx(0.36)


def test_scene_relative_to_request_file(tmp_path, capsys, monkeypatch):
    (tmp_path / "s.yaml").write_text("classes: [line, circle]\n")
    (tmp_path / "r.json").write_text(json.dumps({**GOOD, "scene": "s.yaml"}))
    monkeypatch.chdir(ROOT)
    assert main(["recognize", str(tmp_path / "r.json")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["class"] == "unclassified" and "circle" in out["reason"] and "ellipse" not in out["reason"]


def test_stream_answers_every_line(monkeypatch, capsys):
    lines = [json.dumps(GOOD), "not json", json.dumps({"touches": [{"phi": [1, 2], "x": [1, 2], "y": [1, 2]}]}),
             "", json.dumps(GOOD)]
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(("\n".join(lines) + "\n").encode())))
    assert main(["recognize", "--stream", "-"]) == 0
    out = [json.loads(x) for x in capsys.readouterr().out.splitlines()]
    assert len(out) == 4
    assert out[0]["class"] == out[3]["class"] == "ellipse"
    assert "not valid JSON" in out[1]["error"] and "at least 3 samples" in out[2]["error"]


@pytest.mark.parametrize("payload,msg", [
    ("{", "not valid JSON"),
    ('{"touches": "x"}', "touches"),
    ('{"touches": [{"contact": {"x": 1, "y": 2, "phi": 0, "kappa": NaN, "kappa_s": 0}}]}', "finite"),
    ('{"touches": [{"phi": [1, 2, 3], "x": [1, 2], "y": [1, 2, 3]}]}', "unequal lengths"),
    ('{"touches": [{"contact": {"x": 1, "y": 2, "phi": 0, "kappa": 1, "kappa_s": 0}}]}', "need at least 2"),
    ('{"touches": [], "bogus": 1}', "unknown key"),
    ('{"scene": {"classes": ["blob"]}, "touches": []}', "unknown class"),
])
def test_bad_input_exit_2_one_line(payload, msg):
    r = subprocess.run([sys.executable, "-m", "tools.cli", "recognize", "-"], input=payload, text=True,
                       capture_output=True, cwd=ROOT, timeout=60)
    assert r.returncode == 2 and r.stdout == ""
    assert msg in r.stderr and r.stderr.count("\n") == 1 and "Traceback" not in r.stderr


def test_bad_alpha_and_missing_file(tmp_path, capsys):
    assert main(["recognize", str(tmp_path / "nope.json")]) == 2
    p = tmp_path / "r.json"
    p.write_text(json.dumps(GOOD))
    assert main(["recognize", "--alpha", "2", str(p)]) == 2
    assert "alpha" in capsys.readouterr().err


def test_parse_request_kinds_and_options():
    req = parse_request({"touches": [{"phi": [0.0, 0.1, 0.2], "x": [0, 1, 2], "y": [0, 0.05, 0.2]},
                                     {"contact": {"x": 1, "y": 2, "phi": 0, "kappa": 1, "kappa_s": 0,
                                                  "sigma_kappa": 0.1}},
                                     {"contact": {"x": 1, "y": 2, "phi": 0, "kappa": 1, "kappa_s": 0,
                                                  "cov": [[0.01, 0.0], [0.0, 0.04]]}}],
                         "noise": {"phi": 0.001, "pos": 0.02}, "options": {"refine": True, "alpha": 0.01}})
    assert isinstance(req.touches[0], SamplesTouch) and req.touches[0].contact_index == 1
    assert isinstance(req.touches[1], ContactTouch) and req.touches[1].cov[0, 0] == pytest.approx(0.01)
    assert np.allclose(req.touches[2].cov, [[0.01, 0], [0, 0.04]])
    assert req.noise.pos == 0.02 and req.options == {"refine": True, "alpha": 0.01}
    for bad, msg in (({"options": {"refine": 1}}, "true or false"), ({"options": {"estimator": "x"}}, "estimator"),
                     ({"noise": {"phi": -1}}, ">= 0")):
        with pytest.raises(InputError, match=msg):
            parse_request({"touches": req and [{"contact": {"x": 0, "y": 0, "phi": 0, "kappa": 0, "kappa_s": 0}}] * 3,
                           **bad})


def test_samples_touches_recognized_with_estimator():
    """Dense exact samples on a circle: the estimator's κ, κ_s feed the tree."""
    pytest.importorskip("recognizer.estimate")
    touches = []
    for t0 in (0.2, 1.6, 3.0, 4.4):
        t = t0 + np.linspace(-0.05, 0.05, 11)
        touches.append({"phi": (t + np.pi / 2).tolist(), "x": (100 + 20 * np.cos(t)).tolist(),
                        "y": (20 * np.sin(t)).tolist(), "s": (20 * (t - t[0])).tolist()})
    from recognizer.classify import recognize

    ans = recognize(parse_request({"touches": touches, "scene": {"classes": ["line", "circle", "ellipse"]}})).to_json()
    assert ans["class"] == "circle" and ans["params"]["r"] == pytest.approx(20, rel=1e-3)


SAMPLES_REQ = {"touches": [{"phi": (t + np.pi / 2).tolist(), "x": (100 + 20 * np.cos(t)).tolist(),
                            "y": (20 * np.sin(t)).tolist()}
                           for t in (t0 + np.linspace(-0.05, 0.05, 9) for t0 in (0.2, 1.6, 3.0))]}


@pytest.mark.parametrize("flags,refine,profile", [([], True, "balanced"), (["--profile", "fast"], False, "fast"),
                                                  (["--profile", "accurate"], True, "accurate")])
def test_profile_flag_and_samples_default(flags, refine, profile):
    """Samples-touches get the balanced profile unless a flag (or the request, or its scene)
    says otherwise; --profile sets every option of its profile."""
    from tools.cli import build_parser
    from tools.cmd_recognize import _options

    args = build_parser().parse_args(["recognize", *flags, "-"])
    opts = _options(args, parse_request(SAMPLES_REQ))
    assert opts.refine is refine and opts.profile == profile


@pytest.mark.parametrize("reach,msg", [({"x": 1, "y": 2, "radius": 0}, "radius: must be > 0"),
                                       ({"x": 1, "y": 2, "radius": -3}, "radius: must be > 0"),
                                       ({"x": float("nan"), "y": 2, "radius": 3}, "finite"),
                                       ({"x": 1, "y": float("inf"), "radius": 3}, "finite"),
                                       ({"x": 1, "y": 2}, "missing key 'radius'"),
                                       ({"x": 1, "y": 2, "radius": 3, "z": 0}, "unknown key"),
                                       ([1, 2, 3], "must be a mapping")])
def test_bad_reach_is_bad_input(reach, msg):
    with pytest.raises(InputError, match=msg):
        parse_request({**SAMPLES_REQ, "options": {"reach": reach}})


def test_bad_reach_exits_2_one_line():
    payload = json.dumps({**SAMPLES_REQ, "options": {"reach": {"x": 100, "y": 0, "radius": -1}}})
    r = subprocess.run([sys.executable, "-m", "tools.cli", "recognize", "-"], input=payload, text=True,
                       capture_output=True, cwd=ROOT, timeout=60)
    assert r.returncode == 2 and r.stdout == "" and r.stderr.count("\n") == 1 and "radius" in r.stderr


def test_samples_touch_curvature_round_trips_and_is_validated():
    raw = dict(SAMPLES_REQ["touches"][0], curvature={"kappa": 0.05, "kappa_s": 0.0, "cov": [[1e-6, 0], [0, 1e-8]]})
    req = parse_request({"touches": [raw] * 3})
    k, ks, cov = req.touches[0].curvature
    assert (k, ks) == (0.05, 0.0) and cov[1, 1] == 1e-8
    assert req.touches[0].to_json()["curvature"] == raw["curvature"]
    with pytest.raises(InputError, match="curvature.kappa"):
        parse_request({"touches": [dict(raw, curvature={"kappa": float("nan"), "kappa_s": 0})] * 3})
    # the curvature is its own record: a contact's x, y, phi are not among its keys
    with pytest.raises(InputError, match=r"curvature: unknown key\(s\) x; allowed: kappa, kappa_s, cov"):
        parse_request({"touches": [dict(raw, curvature={"kappa": 0.05, "kappa_s": 0, "x": 1.0})] * 3})
    with pytest.raises(InputError, match=r"curvature: missing key 'kappa_s' \(a curvature has kappa, kappa_s\)$"):
        parse_request({"touches": [dict(raw, curvature={"kappa": 0.05})] * 3})
    with pytest.raises(InputError, match=r"curvature: must be a mapping with kappa, kappa_s and cov or sigma_kappa"):
        parse_request({"touches": [dict(raw, curvature=[0.05, 0.0])] * 3})
    for cov in ([[1e-6, 0], []], [[1e-6], [0, 1e-8]], [[1e-6, 0, 0], [0, 1e-8]], [[1e-6, 0], [0, 1e-8, 0]]):
        with pytest.raises(InputError, match=r"curvature\.cov: must be a 2x2 list"):
            parse_request({"touches": [dict(raw, curvature={"kappa": 0.05, "kappa_s": 0, "cov": cov})] * 3})
