"""recognizer.refine: the Jacobian handed to least_squares (analytic t and pose columns,
forward differences for the shape parameters, memoized model) against central
differences of the residuals themselves."""

from __future__ import annotations

import numpy as np
import pytest

from recognizer import synth
from recognizer.curves import CURVES, Pose
from recognizer.refine import _collect, _initial_t, _Problem


def _problem(cls: str, seed: int, direction: int):
    rng = np.random.default_rng(seed)
    shape = synth.random_shape(cls, rng)
    ts = synth.contact_ts(shape, 3, rng, margin=0.1)
    sn = synth.SynthNoise(1.5e-3, 1e-3 * shape.size)
    touches, tt = synth.sample_shape(shape, ts, 9, 0.02 * shape.size, direction, sn, rng, with_s=False)
    data = _collect(touches)
    # a start off the optimum, so that no residual is ~0 and every column matters
    params = {k: v * 1.02 for k, v in shape.params.items()}
    pose = Pose(shape.pose.theta + 0.01, shape.pose.x + 0.004 * shape.size, shape.pose.y)
    t_contacts = np.array([t[4] for t in tt]) + 0.005
    t0 = _initial_t(cls, params, pose, t_contacts, data, direction)
    problem = _Problem(cls, data, pose, direction, 1.5e-3, 1e-3 * shape.size)
    return problem, problem.pack(params, pose, t0)


def _central(problem: _Problem, z: np.ndarray, f=None) -> np.ndarray:
    """Central differences of ``f`` (default the residuals without the angle wrap)."""
    f = problem._raw if f is None else f
    cols = []
    for i in range(z.size):
        h = 1e-6 * max(abs(z[i]), 1.0)
        zp, zm = z.copy(), z.copy()
        zp[i] += h
        zm[i] -= h
        cols.append((f(zp) - f(zm)) / (2 * h))
    return np.stack(cols, axis=1)


@pytest.mark.parametrize("cls", list(CURVES))
@pytest.mark.parametrize("direction", [1, -1])
def test_jacobian_matches_central_differences(cls, direction):
    problem, z = _problem(cls, 11, direction)
    problem.residuals(z)  # fills the memo, as least_squares does before asking for J
    jac = problem.jacobian(z)
    ref = _central(problem, z)
    scale = np.linalg.norm(ref, axis=0) + 1e-12
    err = np.linalg.norm(jac - ref, axis=0) / scale
    assert err.max() < 1e-4, (cls, err.argmax(), err.max())


def test_memo_follows_z():
    """Residuals and Jacobian at a new z never reuse the previous z's model."""
    problem, z = _problem("ellipse", 3, 1)
    r0 = problem.residuals(z)
    j0 = problem.jacobian(z)
    z2 = z.copy()
    z2[0] += 0.05
    z2[problem.n_glob :] += 0.01
    r2 = problem.residuals(z2)
    j2 = problem.jacobian(z2)
    fresh = _Problem(problem.cls, problem.data, Pose(problem.theta0, *problem.anchor), problem.direction,
                     problem.sig_phi, problem.sig_pos)
    assert np.array_equal(r2, fresh.residuals(z2)) and np.array_equal(j2, fresh.jacobian(z2))
    assert not np.allclose(r0, r2) and not np.allclose(j0, j2)
    # z mutated in place after a call must not leak into the memo
    z3 = z.copy()
    r3 = problem.residuals(z3)
    z3 += 0.1
    assert np.array_equal(problem.residuals(z), r3)


def test_residuals_memo_at_the_same_z():
    """leastsq evaluates its start twice (a shape check, then MINPACK): the second call at the
    same z is the memo's, a fresh array equal to the first to the bit, and a caller that
    writes into the array it got does not change what the next call returns."""
    problem, z = _problem("semicubical_parabola", 5, 1)
    r0 = problem.residuals(z)
    calls = []
    inner = problem._model_at
    problem._model_at = lambda zz, key: calls.append(1) or inner(zz, key)
    r1 = problem.residuals(z.copy())
    assert calls == [] and r1 is not r0 and r1.tobytes() == r0.tobytes()
    r1[:] = 0.0
    assert problem.residuals(z).tobytes() == r0.tobytes()
    z2 = z.copy()
    z2[0] += 1e-3
    problem.residuals(z2)
    assert calls == [1]


@pytest.mark.parametrize("cls", ["ellipse", "cubical_parabola"])
def test_jacobian_across_and_along(cls):
    """With a position deviation along the tangent (``pos_along``) different from across it,
    the position rows are turned into the measured tangent's frame: the Jacobian still
    matches central differences of the residuals."""
    problem, z = _problem(cls, 5, 1)
    aniso = _Problem(problem.cls, problem.data, Pose(problem.theta0, *problem.anchor), problem.direction,
                     problem.sig_phi, problem.sig_pos, sig_along=20 * problem.sig_pos)
    assert aniso.aniso
    aniso.residuals(z)
    jac = aniso.jacobian(z)
    ref = _central(aniso, z, aniso.residuals)
    err = np.linalg.norm(jac - ref, axis=0) / (np.linalg.norm(ref, axis=0) + 1e-12)
    assert err.max() < 1e-4, (err.argmax(), err.max())
    # the rows are a rotation and a rescaling of the isotropic ones: across rows keep their norm
    n = aniso.n_rows
    r_iso, r_an = problem.residuals(z), aniso.residuals(z)
    assert np.allclose(r_iso[:n] ** 2 + r_iso[n:2 * n] ** 2,
                       r_an[:n] ** 2 + (20 * r_an[n:2 * n]) ** 2, rtol=1e-9)


def test_touches_without_a_noise_factor_weighed_as_without_factors():
    """In a fit whitened by noise factors, a touch that states none keeps the per-sample
    weights across and along its tangent: its rows are the anisotropic fit's rows of the
    same samples (one weighting), and the Jacobian still matches central differences."""
    problem, z = _problem("ellipse", 5, 1)
    data, n = problem.data, problem.n_rows
    rows0 = data.factors[0][0]
    k = rows0.size
    factor = np.random.default_rng(2).normal(size=(3 * k, 2 * k)) * 1e-3
    data.factors[0] = (rows0, factor)
    args = (problem.cls, data, Pose(problem.theta0, *problem.anchor), problem.direction, problem.sig_phi,
            problem.sig_pos, 20 * problem.sig_pos)
    aniso, mixed = _Problem(*args), _Problem(*args, factors=True)
    r_an, r_mix = aniso.residuals(z), mixed.residuals(z)
    rank = mixed.whiten[0][1].shape[0]
    expected = np.concatenate([r_an[np.concatenate([rows, n + rows, 2 * n + rows])] for rows, _ in data.factors[1:]])
    assert np.allclose(r_mix[rank:rank + 3 * (n - k)], expected, rtol=1e-12, atol=0)
    jac = mixed.jacobian(z)
    ref = _central(mixed, z, mixed.residuals)
    err = np.linalg.norm(jac - ref, axis=0) / (np.linalg.norm(ref, axis=0) + 1e-12)
    assert err.max() < 1e-4, (err.argmax(), err.max())


def test_within_the_cap_decides_as_entry_by_entry():
    """``refine._within`` (session 32: residuals and Jacobian skip their capping and
    non-finite replacement when it says nothing would change): True only when every entry is
    finite and below the cap; NaN, ±inf, an entry at or beyond the cap, a sum of squares
    above (cap/10)² or one that overflows all answer False (then the entry-by-entry path
    runs)."""
    from recognizer.refine import _within

    cap = 1e30
    assert _within(np.array([1.0, -2e28, 3e-300, 0.0]), cap)
    assert _within(np.zeros((4, 3)), cap)
    for bad in (np.nan, np.inf, -np.inf, cap, -cap, 2e29):
        assert not _within(np.array([1.0, bad, 2.0]), cap)
    with np.errstate(over="ignore"):  # (the callers' errstate)
        assert not _within(np.full(10, 1e160), 1e120)  # finite entries whose squares overflow
    assert _within(np.full((3, 2), 9e117), 1e120)
