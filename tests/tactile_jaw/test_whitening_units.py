"""A jaw's samples touches weigh the same in any unit: their noise factor F is rank-deficient
(3n rows x…, y…, φ… from n + degree + 1 quantities), so the recognizer's whitening by its
pseudo-inverse must not depend on how positions (mm) and angles (rad) are scaled against each
other (recognizer.refine: the pseudo-inverse of F with each row in its own deviation). On main
6613250+i21's scale-free units it did: the P-series cubical example's touches refined to χ² 25.8
in mm, 41.3 in units of 16 mm (refused), 43.0 in units of 32 mm."""

from __future__ import annotations

import math

import numpy as np

from recognizer.classify import recognize
from recognizer.scene import load_scene
from recognizer.touches import Request, SamplesTouch
from recognizer.noise import NoiseModel
from tactile_jaw.pipeline import feel, stated_noise

from tests.tactile_jaw.test_envelope_order import CONFIG, FINE, roll, support_point, touch

SCENE = load_scene("config/scenes/cubical_parabola.yaml")


def _touches():
    """Exact quantized 18° rolls of the left pad on the cubical example at the demo's three
    used touches' pad angles, felt as the exploration feels them."""
    obj, rng = SCENE.object, np.random.default_rng(11)
    out = []
    for centre in (-95.0, -72.5, -105.0):
        psis = math.radians(centre) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
        felt = feel(CONFIG, touch(roll(lambda p: support_point(obj, p), psis, FINE, rng)), 9)
        assert felt.problem is None, felt.problem
        out.append(felt)
    return [f.samples for f in out], stated_noise(out)


INCH = 25.4  # mm: the touches' spread in inches is not a power of two times theirs in mm


def _in_inches(t: SamplesTouch) -> SamplesTouch:
    n, k, ks, cov = len(t.phi), *t.curvature
    factor = np.asarray(t.noise_factor, float).copy()
    factor[: 2 * n] /= INCH
    scale = np.array([INCH, INCH**2])
    return SamplesTouch(t.phi, t.x / INCH, t.y / INCH, t.s / INCH, (k * INCH, ks * INCH**2, cov * np.outer(scale, scale)),
                        factor)


def _chi2(touches, noise: NoiseModel):
    rec = recognize(Request(tuple(touches), SCENE, SCENE.classes, noise, options={"profile": "balanced"}))
    return rec, {r.cls: r.chi2 for r in rec.ranking}


def test_the_same_touches_in_inches_weigh_as_in_mm():
    touches, noise = _touches()
    assert all(np.linalg.matrix_rank(t.noise_factor, 1e-6 * np.linalg.norm(t.noise_factor, 2)) < 3 * len(t.phi)
               for t in touches)  # rank-deficient
    mm, chi_mm = _chi2(touches, noise)
    inch, chi_in = _chi2([_in_inches(t) for t in touches], NoiseModel(noise.phi, noise.pos / INCH, noise.pos_along / INCH))
    assert mm.cls == inch.cls == "cubical_parabola"
    for cls in ("cubical_parabola", "hyperbola"):
        assert math.isclose(chi_mm[cls], chi_in[cls], rel_tol=1e-4), (cls, chi_mm[cls], chi_in[cls])
    assert math.isclose(mm.params["c"], inch.params["c"], rel_tol=1e-5)
    assert math.isclose(mm.params["a"], inch.params["a"] / INCH**2, rel_tol=1e-5)
