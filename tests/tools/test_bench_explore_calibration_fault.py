"""`bench_explore --calibrate` whose calibration is refused or meets a servo's fault ends with
one line and tactile's exit status (3 refused, 1 a fault), not a traceback: a jaw of another
build once refused at the default placements and then overloaded a servo, and the bench printed
the traceback of each."""

from __future__ import annotations

import pytest

from hand_driver.calibration_fit import CalibrationRefused
from hand_driver.errors import ServoHardwareError
from tools import bench_explore


@pytest.mark.parametrize("exc, status", [
    (CalibrationRefused("placement 1: this jaw's pads reach 0 locating touches"), 3),
    (ServoHardwareError(4, 0x20, ["overload error"]), 1),
])
def test_a_refused_or_faulted_calibration_is_one_line(exc, status, monkeypatch, capsys, tmp_path):
    def refuse(*args, **kwargs):
        raise exc

    monkeypatch.setattr(bench_explore, "calibrated_config", refuse)
    code = bench_explore.main(["--finite", "1", "--classes", "line", "--config", "config/jaw-p.yaml",
                               "--truth-config", "config/jaw-p-truth.yaml", "--calibrate", "--keep", str(tmp_path)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == status
    assert len(err) == 1 and err[0].startswith("bench_explore: calibration of config/jaw-p.yaml") and str(exc) in err[0]
