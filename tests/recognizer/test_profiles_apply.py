"""Profiles reach the recognizer: flags > request options > request profile > scene profile."""

from types import SimpleNamespace

from recognizer.classify import options_for
from recognizer.touches import NoiseModel


def _req(options=None, scene_profile=None):
    scene = SimpleNamespace(profile=scene_profile) if scene_profile is not None else None
    return SimpleNamespace(options=options or {}, scene=scene, noise=NoiseModel(1e-3, 0.05))


def test_profile_precedence():
    assert options_for(_req()).refine is False  # no profile: defaults
    assert options_for(_req(scene_profile="balanced")).refine is True  # the scene's profile
    o = options_for(_req({"profile": "fast"}, scene_profile="accurate"))  # request's beats scene's
    assert o.refine is False and o.profile == "fast"
    o = options_for(_req({"profile": "fast", "refine": True}))  # explicit key beats its profile
    assert o.refine is True and o.estimator == "auto"
    o = options_for(_req({"profile": "balanced", "alpha": 0.01}), {"alpha": 0.05, "estimator": "central"})
    assert o.alpha == 0.05 and o.estimator == "central" and o.refine is True  # flags beat all
    assert options_for(_req()).noise == NoiseModel(1e-3, 0.05)
