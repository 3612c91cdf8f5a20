"""Fixtures of the command-line tests."""

from __future__ import annotations

import contextlib
import io
import json

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
