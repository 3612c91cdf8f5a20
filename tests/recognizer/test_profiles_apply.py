"""Profiles reach the recognizer: flags > request options > request profile > scene profile
> balanced for samples-touches; a request of contacts only keeps the invariants-only default."""

from types import SimpleNamespace

import numpy as np

from recognizer.classify import options_for
from recognizer.touches import ContactTouch, NoiseModel, SamplesTouch

SAMPLES = SamplesTouch(np.zeros(3), np.arange(3.0), np.zeros(3))
CONTACT = ContactTouch(0.0, 0.0, 0.0, 0.1, 0.0)


def _req(options=None, scene_profile=None, touches=(SAMPLES,)):
    scene = SimpleNamespace(profile=scene_profile) if scene_profile is not None else None
    return SimpleNamespace(options=options or {}, scene=scene, noise=NoiseModel(1e-3, 0.05), touches=touches)


def test_profile_precedence():
    o = options_for(_req())  # samples-touches, no profile anywhere: balanced
    assert o.refine is True and o.profile == "balanced"
    assert options_for(_req(touches=(CONTACT,) * 3)).refine is False  # contacts only: invariants
    assert options_for(_req(touches=(CONTACT,) * 3, scene_profile="balanced")).refine is True  # the scene's
    o = options_for(_req({"profile": "fast"}, scene_profile="accurate"))  # request's beats scene's
    assert o.refine is False and o.profile == "fast"
    o = options_for(_req({"profile": "fast", "refine": True}))  # explicit key beats its profile
    assert o.refine is True and o.estimator == "auto"
    o = options_for(_req({"profile": "balanced", "alpha": 0.01}), {"alpha": 0.05, "estimator": "central"})
    assert o.alpha == 0.05 and o.estimator == "central" and o.refine is True  # flags beat all
    o = options_for(_req({"profile": "balanced", "alpha": 0.01}), {"profile": "fast"})  # --profile: all of fast
    assert o.refine is False and o.alpha == 1e-3 and o.profile == "fast"
    assert options_for(_req()).noise == NoiseModel(1e-3, 0.05)
