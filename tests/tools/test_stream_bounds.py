"""The recognition stream and its reader within bounds (issue 22): a line that never ends is
refused while it is read, options must be an object, every documented limit holds on every
numeric field, and no RuntimeWarning reaches stderr."""

from __future__ import annotations

import copy
import io
import os
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import pytest

from recognizer.curves import Pose
from recognizer.touches import parse_request
from tactile_common.errors import InputError
from tools import cmd_recognize
from tools.bench_recognizer import exact_request

ROOT = Path(__file__).resolve().parents[2]
CONTACTS = exact_request("ellipse", {"a": 28.6, "b": 17.3}, [0.36, 1.86, 4.23], Pose(0.3, 120.0, 15.0), False)
SAMPLES = {"touches": [{"phi": [0.1 * k + 0.01 * j for j in range(5)], "x": [10.0 * k + j for j in range(5)],
                        "y": [0.5 * j * j for j in range(5)]} for k in range(3)], "noise": {"phi": 1e-3, "pos": 0.01}}


class _Zeros(io.RawIOBase):
    """An endless stream of NUL bytes (what ``cat /dev/zero`` gives), counting what was read."""

    def __init__(self) -> None:
        self.read_bytes = 0

    def readable(self) -> bool:
        return True

    def readinto(self, b) -> int:
        b[:] = bytes(len(b))
        self.read_bytes += len(b)
        return len(b)


def test_an_endless_line_is_refused_while_it_is_read():
    raw = _Zeros()
    lines = cmd_recognize._lines(io.BufferedReader(raw), cmd_recognize.MAX_LINE_BYTES)
    t0 = time.perf_counter()
    assert next(lines) == (1, None)  # answered as soon as the limit is passed
    assert raw.read_bytes <= cmd_recognize.MAX_LINE_BYTES + 2 ** 17
    with pytest.raises(cmd_recognize._Endless, match="line 1: no end of line within"):
        next(lines)
    assert time.perf_counter() - t0 < 5.0
    assert raw.read_bytes <= cmd_recognize.MAX_LINE_BYTES + cmd_recognize.MAX_SKIP_BYTES + 2 ** 18


def test_zeros_into_the_service_end_with_a_clear_refusal():
    """``cat /dev/zero | tactile recognize - --stream`` ran at 50 % CPU forever."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "recognize", "-", "--stream"], cwd=ROOT, env=env,
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)

    def feed():
        chunk = bytes(1 << 16)
        try:
            while True:
                proc.stdin.write(chunk)
        except (BrokenPipeError, ValueError, OSError):
            pass

    threading.Thread(target=feed, daemon=True).start()
    try:
        proc.wait(timeout=60)  # the answers are two short lines: no pipe fills meanwhile
    finally:
        proc.kill()
    out, err = proc.stdout.read(), proc.stderr.read()
    lines = out.decode().splitlines()
    assert proc.returncode == 2
    assert lines[0] == f'{{"error": "line 1: longer than {cmd_recognize.MAX_LINE_BYTES} bytes (the request limit)"}}'
    assert "no end of line within" in lines[1] and len(lines) == 2
    assert err.decode().count("\n") == 1 and "Traceback" not in err.decode()


@pytest.mark.parametrize("options", [[], 0, "", False, "refine"])
def test_options_that_are_not_an_object_are_refused(options):
    """``"options": []``, ``0``, ``""`` and ``false`` passed as "no options"."""
    with pytest.raises(InputError, match=r"request\.options: must be a mapping"):
        parse_request({**CONTACTS, "options": options})
    assert parse_request({**CONTACTS, "options": None}).options == {}


def _strict(obj):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return parse_request(obj)


def _with_curvature(**curv):
    req = copy.deepcopy(SAMPLES)
    req["touches"][1]["curvature"] = {"kappa": 0.01, "kappa_s": 0.0, "sigma_kappa": 1e-3, "sigma_kappa_s": 1e-4, **curv}
    return req


@pytest.mark.parametrize("req,msg", [
    (_with_curvature(kappa=1e300), r"touches\[1\]\.curvature\.kappa: \|1e\+300\| is beyond"),  # was accepted, ignored
    (_with_curvature(kappa_s=-1e200), r"touches\[1\]\.curvature\.kappa_s: \|-1e\+200\| is beyond"),
    (_with_curvature(sigma_kappa=1e100), r"touches\[1\]\.curvature: sigma of kappa"),
    ({**SAMPLES, "options": {"reach": {"x": 1e300, "y": 0, "radius": 1}}}, r"options\.reach\.x: .* beyond 1e\+06"),
    ({**SAMPLES, "noise": {"phi": 1e-3, "pos": 5e-324}}, r"noise\.pos: 4\.94e-324 is below 1e-12"),
])
def test_every_numeric_field_is_held_to_its_limit(req, msg):
    with pytest.raises(InputError, match=msg):
        _strict(req)


@pytest.mark.parametrize("value", [1e200, 1e155])
def test_an_overflowing_cov_is_refused_without_a_warning(value):
    req = copy.deepcopy(CONTACTS)
    req["touches"][0]["contact"]["cov"] = [[value, 0.0], [0.0, value]]
    with pytest.raises(InputError, match=r"touches\[0\]\.contact: sigma of kappa"):
        _strict(req)
    req["touches"][0]["contact"]["cov"] = [[value, 2 * value], [2 * value, value]]
    with pytest.raises(InputError, match=r"cov: must be positive semi-definite"):
        _strict(req)


def test_a_denormal_noise_factor_is_refused_without_a_warning():
    """A denormal entry overflowed the whitening (RuntimeWarning on stderr, then an answer)."""
    req = copy.deepcopy(SAMPLES)
    req["touches"][0]["noise_factor"] = [[5e-324 if i == j else 0.0 for j in range(15)] for i in range(15)]
    with pytest.raises(InputError, match=r"touches\[0\]\.noise_factor: an entry of 4\.94e-324 is below 1e-12"):
        _strict(req)
    req["touches"][0]["noise_factor"] = [[1e-3 if i == j else 0.0 for j in range(15)] for i in range(15)]
    assert _strict(req).touches[0].noise_factor.shape == (15, 15)
