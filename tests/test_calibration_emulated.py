"""End-to-end calibration on the emulated bus: a truth jaw whose zero ticks differ by up
to ±20 ticks and links by up to ±1 mm from the nominal config touches the reference disk
at the three suggested placements through the real driver stack (Protocol 2.0 over a
pty, JointBus, guarded touches). Measured: links and pad offsets come back within
~0.1 mm and the distal zero ticks within ~0.5 tick, but the base joints' zero ticks only
to ~0.6 tick standard error (errors up to ~1.3 ticks): the issue's 1-tick target is not
met reliably by this touch plan (README, section kinematics). So the test checks what
holds: every error within 3 standard errors (honest uncertainties), a large residual
drop, and that the default tolerances refuse rather than write a config they cannot
vouch for."""

from __future__ import annotations

import dataclasses

import numpy as np

from hand_driver import calibration as cal
from hand_driver.bus import JointBus
from hand_driver.config import dump_config, load_config
from hand_driver.motion import Jaw, LockstepClock
from hand_driver.sim.server import EmulatedBus
from recognizer.curves import Pose
from recognizer.scene import load_scene

CFG = load_config("config/jaw.yaml")
DISK = load_scene("config/scenes/calibration.yaml").object


def test_calibration_on_the_emulated_bus_recovers_the_truth(tmp_path):
    rng = np.random.default_rng(11)
    fingers = []
    for f in CFG.fingers:
        joints = tuple(dataclasses.replace(j, zero_tick=j.zero_tick + rng.choice([-1, 1]) * rng.uniform(10, 20),
                                           link_mm=j.link_mm + rng.choice([-1, 1]) * rng.uniform(0.5, 1.0))
                       for j in f.joints)
        fingers.append(dataclasses.replace(f, joints=joints,
                                           pad=dataclasses.replace(f.pad, offset_mm=f.pad.offset_mm + 0.3)))
    truth = dataclasses.replace(CFG, fingers=tuple(fingers))
    readings = []
    for k, (x, y) in enumerate(cal.DEFAULT_PLACEMENTS):
        disk = dataclasses.replace(DISK, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
        with EmulatedBus(CFG, disk, truth_config=truth, time_scale=0.0) as sim, \
                JointBus(sim.port, CFG.bus.baudrate, CFG.joints, handle_signals=False) as bus:
            jaw = Jaw(bus, CFG, clock=LockstepClock(sim))
            got, center, _ = cal.touch_reference(jaw, DISK, (x, y), placement=k, faces=6, corners=4)
        assert np.hypot(center[0] - disk.pose.x, center[1] - disk.pose.y) < 5.0  # located (nominal geometry)
        readings += got
    loose = {"zero_tick": 5.0, "link_mm": 0.5, "offset_mm": 0.5}
    result = cal.fit(CFG, DISK, readings, tolerances=loose)
    err = cal._pack(result.config) - cal._pack(truth)
    for e, d in zip(result.estimates, err):
        assert abs(d) <= 3.0 * e.se + 0.05, f"{e.name}: error {d:+.3f} (se {e.se:.3f})"
        assert abs(d) <= (2.0 if e.kind == "zero_tick" else 0.2), f"{e.name}: error {d:+.3f}"
    assert result.rms_before_mm > 0.3 and result.rms_after_mm < 0.06
    out = tmp_path / "calibrated.yaml"
    dump_config(result.config, out)
    assert load_config(out) == result.config
    try:
        strict = cal.fit(CFG, DISK, readings)
    except cal.CalibrationRefused as exc:
        assert "only to" in str(exc)
    else:
        err = cal._pack(strict.config) - cal._pack(truth)
        for e, d in zip(strict.estimates, err):
            assert abs(d) <= (1.0 if e.kind == "zero_tick" else 0.1)
