"""Fixtures of the command-line tests."""

from __future__ import annotations

import contextlib
import io
import json
import signal
import subprocess
import sys
import time

import pytest
import yaml

from tools.cli import main


def _tactile_in_process(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


@pytest.fixture(scope="session")
def tactile_in_process():
    """``tactile_in_process(argv)`` → (exit status, stdout, stderr) of ``tactile ARGV`` run
    in the test's own process (the emulated bus and the recognizer as a user gets them)."""
    return _tactile_in_process


def _demo_answer(scene: dict, path, log=None, config: str | None = None) -> dict:
    path.write_text(yaml.safe_dump(scene))
    rc, out, err = _tactile_in_process(["demo", "--scene", str(path), "--json"]
                                       + (["--log", str(log)] if log is not None else [])
                                       + (["--config", config] if config is not None else []))
    answer = json.loads(out)
    assert "Traceback" not in err and rc == (3 if answer["class"] == "unclassified" else 0), err
    return answer


@pytest.fixture(scope="session")
def demo_answer():
    """``demo_answer(scene mapping, scene path, log path or None, config=None)`` → the JSON
    answer of ``tactile demo`` on that scene (with that jaw config), written to the path
    (exit 0, or 3 for a refusal, and no traceback asserted)."""
    return _demo_answer


@pytest.fixture(scope="session")
def default_demo(tmp_path_factory):
    """``tactile demo`` on the default scene as the README shows it (text output), with
    ``--log`` and ``--mcap``: one run shared by the docs' and the bag's tests."""
    d = tmp_path_factory.mktemp("default_demo")
    log, bag = d / "demo.jsonl", d / "demo.mcap"
    rc, out, err = _tactile_in_process(["demo", "--log", str(log), "--mcap", str(bag)])
    assert rc == 0 and "Traceback" not in err, err
    return {"out": out, "err": err, "log": log, "mcap": bag, "dir": d}


def _killed_demo(log, *extra: str, readings: int = 60, timeout_s: float = 60.0) -> None:
    """``tactile demo --log LOG EXTRA...`` in its own process, SIGKILLed once the log holds
    ``readings`` readings (or after ``timeout_s``): what a crash of the host leaves."""
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "demo", "--log", str(log), *extra],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            if log.exists() and log.read_text().count('"type":"reading"') >= readings:
                break
            time.sleep(0.05)
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait()


@pytest.fixture(scope="session")
def killed_demo():
    """``killed_demo(log, *extra_args, readings=60, timeout_s=60)``: a demo killed mid-run."""
    return _killed_demo
