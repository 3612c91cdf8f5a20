"""A calibrated config written from the one it calibrated (hand_driver.config.dump_config
with ``source``) keeps that file's comments and layout; only changed values differ."""

from __future__ import annotations

from dataclasses import replace

from hand_driver.config import dump_config, load_config

SOURCE = "config/jaw.yaml"


def _calibrated(cfg):
    f0, f1 = cfg.fingers
    j = replace(f0.joints[0], zero_tick=2047.37, link_mm=80.123)
    pad = replace(f1.pad, offset_mm=7.91)
    return replace(cfg, fingers=(replace(f0, joints=(j, f0.joints[1])), replace(f1, pad=pad)))


def test_rewritten_config_keeps_comments_and_reads_back_equal(tmp_path):
    cfg = _calibrated(load_config(SOURCE))
    out = tmp_path / "calibrated.yaml"
    dump_config(cfg, out, header="calibrated by a test", source=SOURCE)
    assert load_config(out) == cfg
    text, src = out.read_text(), open(SOURCE).read()
    assert text.startswith("# calibrated by a test\n# Default jaw: two planar fingers")
    comments = [line for line in src.splitlines() if "#" in line]
    assert comments and all(line in text for line in comments)  # every comment, inline ones too
    changed = [(a, b) for a, b in zip(src.splitlines(), text.splitlines()[1:]) if a != b]
    assert len(text.splitlines()) == len(src.splitlines()) + 1 and len(changed) == 2  # two lines changed
    assert "zero_tick: 2047.37, link_mm: 80.123" in changed[0][1] and "offset_mm: 7.91" in changed[1][1]


def test_unreadable_source_still_writes_the_config(tmp_path):
    cfg = _calibrated(load_config(SOURCE))
    out = tmp_path / "calibrated.yaml"
    dump_config(cfg, out, source=tmp_path / "gone.yaml")
    assert load_config(out) == cfg


def test_keys_the_calibration_adds_or_drops(tmp_path):
    """A P-series calibration adds ``backlash_deg`` and ``zero_sigma_deg`` to joints whose
    source has none (``tactile calibrate`` crashed here with a KeyError) and may drop one
    the source had; the output reads back equal and keeps the source's comments."""
    src = "config/jaw-p.yaml"
    cfg = load_config(src)
    f0, f1 = cfg.fingers
    j0 = replace(f0.joints[0], zero_tick=335.25, backlash_deg=0.1003, zero_sigma_deg=0.0004)
    cfg = replace(cfg, fingers=(replace(f0, joints=(j0, f0.joints[1])), f1))
    out = tmp_path / "calibrated.yaml"
    dump_config(cfg, out, source=src)
    assert load_config(out) == cfg
    text = out.read_text()
    assert "backlash_deg: 0.1003" in text and "zero_sigma_deg: 0.0004" in text
    assert all(line in text for line in open(src).read().splitlines() if line.startswith("#"))
    back = replace(cfg, fingers=(replace(f0, joints=(replace(j0, backlash_deg=0.0), f0.joints[1])), f1))
    out2 = tmp_path / "dropped.yaml"
    dump_config(back, out2, source=out)
    assert load_config(out2) == back and "backlash_deg" not in out2.read_text()
