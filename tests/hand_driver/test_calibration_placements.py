"""Where `tactile calibrate` asks for the reference disk when no --place is given
(hand_driver.calibration.default_placements): the default pattern on the shipped geometry, moved
away from the palm on a jaw whose pads cannot fold round a disk at (60, 0) mm."""

from __future__ import annotations

from pathlib import Path

import pytest

from hand_driver.calibration import _locate_options, default_placements
from hand_driver.calibration_fit import CalibrationRefused
from hand_driver.calibration_plan import DEFAULT_PLACEMENTS
from hand_driver.config import load_config
from recognizer.scene import load_scene

DISK = load_scene("config/scenes/calibration.yaml").object


def _long_links(tmp_path: Path):
    """config/jaw-p.yaml with 85 / 62 mm links and 40 mm pads (a P-series jaw of another build)."""
    text = Path("config/jaw-p.yaml").read_text()
    text = text.replace("link_mm: 80.0", "link_mm: 85.0").replace("link_mm: 65.0", "link_mm: 62.0")
    text = text.replace("length_mm: 52.0", "length_mm: 40.0")
    path = tmp_path / "jaw-long.yaml"
    path.write_text(text)
    return load_config(path)


def test_the_shipped_jaw_locates_the_disk_at_the_default_placements():
    cfg = load_config("config/jaw.yaml")
    options = _locate_options(cfg, DISK, DEFAULT_PLACEMENTS[0])
    assert sum(len(v) for v in options.values()) >= 4  # (60, 0): 4 per finger
    assert default_placements(cfg, DISK) == list(DEFAULT_PLACEMENTS)


def test_a_jaw_of_longer_links_gets_the_pattern_moved_out(tmp_path):
    """With 85 / 62 mm links and 40 mm pads no locating touch of a disk at (60, 0) mm is
    reachable from the parking poses (the command used to touch nothing there and ask for the
    disk where it lay); 10 mm farther, each placement leaves ≥ 4."""
    cfg = _long_links(tmp_path)
    assert sum(len(v) for v in _locate_options(cfg, DISK, DEFAULT_PLACEMENTS[0]).values()) == 0
    places = default_placements(cfg, DISK)
    assert places == [(x + 10.0, y) for x, y in DEFAULT_PLACEMENTS]
    for p in places:
        assert sum(len(v) for v in _locate_options(cfg, DISK, p).values()) >= 4


def test_no_shift_that_works_is_a_refusal(tmp_path, monkeypatch):
    import hand_driver.calibration as cal

    monkeypatch.setattr(cal, "PLACEMENT_SHIFT_MAX_MM", 5.0)
    with pytest.raises(CalibrationRefused, match="pass --place X,Y"):
        default_placements(_long_links(tmp_path), DISK)
