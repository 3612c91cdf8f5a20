"""Fixtures of the command-line tests."""

from __future__ import annotations

import contextlib
import io

import pytest

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
