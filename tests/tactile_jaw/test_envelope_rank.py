"""The order rule fits no degree of d(ψ) the readings cannot determine
(hand_driver.kinematics.determined_degree, tactile_jaw.envelope.choose_degree): the scan of a
flat press that pivoted about corners and slid a pad end (P-series line 16 of bench_explore
--finite 20 --anywhere --seed 173, its right pad's 30 lines over 58°), which
tactile_jaw.pipeline.curved_part feels as a roll, stepped up to degree 26 and fitted degrees
25 and 26 rank-deficient (numpy's RankWarning on `tactile replay`)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from tactile_jaw.envelope import degrees, fit_envelope

RIGHT = load_config("config/jaw-p.yaml").finger("right")

#: the scan's joint angles (rad), in the order the press read them
SCAN_Q = np.array([
    [0.1643142282, -0.1817728095], [0.1530290479, -0.1181238838], [0.1424198517, -0.0551575757],
    [0.1337134259, 0.0059160197], [0.1247190808, 0.0672688679], [0.1153867437, 0.1289630248],
    [0.1056287869, 0.1910915749], [0.0953763602, 0.2536958887], [0.0845167996, 0.3169104214],
    [0.0729499592, 0.3808385998], [0.0605193613, 0.4456252216], [0.0470560097, 0.5114461127],
    [0.0323345765, 0.5785288121], [0.0133381693, 0.6498830433], [-0.0176131433, 0.7332037689],
    [0.0505298173, 0.4948771203], [0.0539285155, 0.4783908695], [0.0572583635, 0.4619770175],
    [0.0435008337, 0.5280875039], [0.0398642892, 0.5448219793], [0.0361526353, 0.5616185109],
    [0.0284288902, 0.5955218548], [0.0244167989, 0.6126286672], [0.0202983027, 0.6298285637],
    [-0.0530710171, 0.8210132228], [-0.094919445, 0.915224803], [-0.1464694977, 1.0191378282],
    [-0.2147877135, 1.1398163568], [-0.3214116993, 1.2987938735], [-0.3632976819, 1.3537652807]])


def _warns(psi, d, degree: int) -> bool:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", np.exceptions.RankWarning)
        kin.touch_from_pad_lines(psi, d, degree=degree)
    return any(issubclass(w.category, np.exceptions.RankWarning) for w in caught)


def test_the_determined_degree_is_the_highest_numpy_fits_at_full_rank():
    lines = kin.finger_pad_line(RIGHT, SCAN_Q)
    top = kin.determined_degree(lines.psi)
    assert top < degrees(len(SCAN_Q)).stop - 1  # the order rule could step past it
    assert not _warns(lines.psi, lines.d, top)
    assert _warns(lines.psi, lines.d, top + 1)


@pytest.mark.parametrize("n", [3, 5, 9, 15])
def test_spread_readings_determine_every_degree(n):
    psi = np.radians(np.linspace(60.0, 78.0, n))  # a roll's even steps
    assert kin.determined_degree(psi[::-1]) == n - 1


def test_a_flat_press_scan_is_fitted_at_full_rank_only():
    lines = kin.finger_pad_line(RIGHT, SCAN_Q)
    with warnings.catch_warnings():
        warnings.simplefilter("error", np.exceptions.RankWarning)
        fit = fit_envelope(RIGHT, SCAN_Q, lines)
    top = kin.determined_degree(lines.psi)
    assert fit.contacts.degree <= top and fit.kappa_degree <= top
    assert np.isfinite(fit.kappa) and np.all(np.isfinite(fit.cov))
