"""A run log proves it is whole (issue 22): record numbers and a hash chain, cross-checks a
reader can make, a cut told from damage; version 1 logs still read, unverified."""

from __future__ import annotations

import errno
import json
from dataclasses import dataclass
from pathlib import Path

import pytest

from hand_driver.config import config_to_mapping, load_config
from hand_driver.log import LogWriteError, RunLog, read_log
from tactile_common.errors import InputError
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
CONFIG = config_to_mapping(load_config(ROOT / "config/jaw.yaml"))
N = sum(len(f["joints"]) for f in CONFIG["fingers"])
LEFT, RIGHT = (f["name"] for f in CONFIG["fingers"])


@dataclass
class _State:
    t_monotonic: float
    ticks: tuple
    current_ma: tuple | None = None
    moving: tuple | None = None


def _run(log: RunLog, touches: int = 2, samples: int = 3) -> None:
    """What an exploration writes: readings, touches of ``samples`` samples, events, the result."""
    t = 0.0
    for k in range(touches):
        finger = (LEFT, RIGHT)[k % 2]
        t += 0.01
        i = log.reading(_State(t, (2048 + k,) * N))
        log.write({"type": "touch_start", "touch": k, "finger": finger, "psi": 0.1 * k, "reading": i})
        for m in range(samples):
            t += 0.01
            i = log.reading(_State(t, (2050 + m,) * N, (1.0,) * N, (False,) * N))
            log.write({"type": "sample", "touch": k, "finger": finger, "psi": 0.1 * k + 0.01 * m, "reading": i,
                       "by": "current"})
        log.write({"type": "touch_end", "touch": k, "finger": finger, "reading": i, "samples": samples,
                   "outcome": "ok"})
    log.event("touch_used", "left: touch 0 used", touch=0)
    log.write({"type": "result", "recognition": None, "robot_time_s": t})


@pytest.fixture
def whole_log(tmp_path) -> Path:
    path = tmp_path / "run.jsonl"
    with RunLog(path).open(config=CONFIG, scene=None, command=["test"]) as log:
        _run(log)
    return path


def _lines(path: Path) -> list[str]:
    return path.read_text().splitlines(keepends=True)


def _line_of(lines: list[str], kind: str, nth: int = 0) -> int:
    """Index of the nth record of a type."""
    return [k for k, s in enumerate(lines) if json.loads(s)["type"] == kind][nth]


def test_a_whole_log_is_verified(whole_log, capsys):
    c = read_log(whole_log)
    assert c.verified and not c.truncated and c.cut is None and c.version == 2
    recs = [json.loads(s) for s in _lines(whole_log)]
    assert [r["seq"] for r in recs] == list(range(len(recs)))
    assert recs[-1]["type"] == "end" and all(len(r["h"]) == 16 for r in recs)
    assert main(["replay", "--verify", str(whole_log)]) == 0
    assert "whole: 22 records, hash chain verified" in capsys.readouterr().out


def _rewrite(path: Path, lines: list[str]) -> None:
    path.write_text("".join(lines))


# Each case of issue 22's "Why", on a log the current writer wrote: every one was read
# without complaint (exit 0) before the log carried its record numbers and hash chain.
def _duplicate_samples(lines):
    first = _line_of(lines, "sample")
    return lines[:first + 1] + [lines[first]] * 4 + lines[first + 1:]


def _delete_a_sample(lines):
    del lines[_line_of(lines, "sample", 1)]
    return lines


def _sample_after_result(lines):
    k = _line_of(lines, "result") + 1
    return lines[:k] + [lines[_line_of(lines, "sample", 4)]] + lines[k:]


def _sample_at_an_earlier_reading(lines):
    k = _line_of(lines, "sample", 3)  # touch 1's first sample names a reading of touch 0
    lines[k] = lines[k].replace('"reading":', '"reading":0,"was":').replace('"reading": ', '"reading": 0, "was": ')
    return lines


def _swap_a_touchs_finger(lines):
    return [s.replace(f'"finger":"{LEFT}"', f'"finger":"{RIGHT}"') if '"touch":0,' in s else s for s in lines]


@pytest.mark.parametrize("damage", [_duplicate_samples, _delete_a_sample, _sample_after_result,
                                    _sample_at_an_earlier_reading, _swap_a_touchs_finger])
def test_why_cases_are_line_n_exit_2(whole_log, damage, capsys):
    _rewrite(whole_log, damage(_lines(whole_log)))
    with pytest.raises(InputError, match=r"run\.jsonl: line \d+: "):
        read_log(whole_log)
    assert main(["replay", str(whole_log)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and ": line " in err and "Traceback" not in err


def _as_version_1(lines: list[str]) -> list[str]:
    out = []
    for s in lines:
        r = json.loads(s)
        if r["type"] == "end":
            continue
        r.pop("seq"), r.pop("h")
        if r["type"] == "header":
            r["version"] = 1
        out.append(json.dumps(r) + "\n")
    return out


@pytest.mark.parametrize("damage,msg", [
    (_duplicate_samples, "not after the touch's previous sample"),
    (_delete_a_sample, "touch_end counts 3 samples, the log holds 2"),
    (_sample_after_result, "a 'sample' record after the result"),
    (_sample_at_an_earlier_reading, "before its touch started"),
])
def test_version_1_logs_are_cross_checked(whole_log, damage, msg):
    """Without a hash chain, the reader's cross-checks still catch these."""
    _rewrite(whole_log, damage(_as_version_1(_lines(whole_log))))
    with pytest.raises(InputError, match=rf"line \d+: .*{msg}"):
        read_log(whole_log)


def test_old_logs_read_and_say_they_cannot_be_verified(whole_log, capsys):
    _rewrite(whole_log, _as_version_1(_lines(whole_log)))
    c = read_log(whole_log)
    assert not c.verified and c.version == 1 and len(c.touches) == 2
    assert main(["replay", "--verify", str(whole_log)]) == 0
    assert "cannot be verified" in capsys.readouterr().out


@pytest.mark.parametrize("keep", [1, 5, 12, 18])
def test_a_cut_at_a_record_boundary_is_said(whole_log, keep, capsys):
    lines = _lines(whole_log)
    _rewrite(whole_log, lines[:keep])
    c = read_log(whole_log)
    assert c.truncated and c.records == keep and "without its end record" in c.cut
    assert main(["replay", "--verify", str(whole_log)]) == 0
    assert "the run was cut" in capsys.readouterr().out


def test_a_cut_mid_record_reads_up_to_the_last_whole_one(whole_log):
    raw = whole_log.read_bytes()
    for cut in (len(raw) - 1, len(raw) - 20, raw.index(b"\n", 300) + 7):
        whole_log.write_bytes(raw[:cut])
        c = read_log(whole_log)
        assert c.truncated and "cut mid-record" in c.cut and c.records == raw[:cut].count(b"\n")


@pytest.mark.parametrize("edit,msg", [
    (lambda s: s.replace('"psi":0.01,', '"psi":0.02,'), "the record is not what was written"),
    (lambda s: s.replace('"seq":6,', '"seq":7,'), "record number 7, expected 6"),
    (lambda s: s.replace(',"h":"', ',"x":"'), "no hash"),
    (lambda s: s.replace('"seq":6,', ''), "record number None"),
])
def test_an_edited_record_is_named(whole_log, edit, msg):
    lines = _lines(whole_log)
    assert '"psi":0.01,' in lines[6] and '"seq":6,' in lines[6]  # the second sample of touch 0
    lines[6] = edit(lines[6])
    _rewrite(whole_log, lines)
    with pytest.raises(InputError, match=rf"line 7: {msg}"):
        read_log(whole_log)


def test_records_after_the_end_are_refused(whole_log):
    lines = _lines(whole_log)
    _rewrite(whole_log, lines + lines[1:2])
    with pytest.raises(InputError, match=rf"line {len(lines) + 1}: record number"):
        read_log(whole_log)


def test_a_full_disk_stops_the_run_and_leaves_the_log_whole(tmp_path, monkeypatch):
    """ENOSPC on the 9th record: LogWriteError (a DeviceFault: exit 1, torque off by the bus's
    context), nothing more is written, and the log reads as cut after its last whole record."""
    import hand_driver.log as log_module

    path = tmp_path / "run.jsonl"
    real_fsync, count = log_module.os.fsync, [0]

    class _FullDisk:
        def __init__(self, f):
            self.f = f

        def write(self, data):
            count[0] += 1
            if count[0] >= 9:
                n = self.f.write(bytes(data[:10]))  # a short write, then the disk is full
                if count[0] > 9:
                    raise OSError(errno.ENOSPC, "No space left on device")
                return n
            return self.f.write(data)

        def fileno(self):
            return self.f.fileno()

        def close(self):
            self.f.close()

    monkeypatch.setattr(log_module.os, "fsync", real_fsync)
    log = RunLog(path).open(config=CONFIG, scene=None)
    log._file = _FullDisk(log._file)
    with pytest.raises(LogWriteError, match=r"--log .*run\.jsonl: cannot write the run log \(No space left on device\)"):
        with log:
            _run(log)
    c = read_log(path)
    assert c.truncated and "cut mid-record" in c.cut and c.records == 9
