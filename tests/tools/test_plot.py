"""tools.plot draws every touch form the exploration hands the recognizer: a flat press's
seat comes as a contact touch (docs/formats.md), not samples."""

from __future__ import annotations

import pytest

pytest.importorskip("matplotlib")

from tools.plot import plot_exploration  # noqa: E402


def test_a_line_from_flat_presses_is_plotted(tmp_path):
    """Three seats of one face (contact touches), answered line: the plot is written (it
    raised KeyError 'x' on contact touches: `tactile demo --plot` of a block pressed flat)."""
    seat = {"x": 100.09, "y": 5.48, "phi": -2.5089, "kappa": 0.0, "kappa_s": 0.0,
            "cov": [[6.6e-07, 0.0], [0.0, 7.0e-09]]}
    touches = [{"contact": dict(seat, x=seat["x"] + 1e-3 * k), "finger": "right"} for k in range(3)]
    recognition = {"class": "line", "params": {}, "pose": {"theta": -2.5089, "x": 32.39, "y": -44.16},
                   "contacts": [{"t": -83.957, "x": 100.09, "y": 5.48}] * 3}
    out = plot_exploration(tmp_path / "press.png", touches=touches,
                           pad_segments=[{"finger": "right", "p0": (90.0, -2.0), "p1": (110.0, 13.0)}],
                           recognition=recognition, truth=None, workspace=((110.0, 0.0), 45.0))
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
