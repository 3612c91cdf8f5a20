"""The exploration's stopping rule (hand_driver.explore.indecision / final_answer) on
hand-made rankings: which answers are decisive, and that an undecided one becomes a
reasoned refusal rather than a class."""

import math

from scipy import stats

from hand_driver.explore import DECISIVE_BIC, ExploreSettings, final_answer, indecision
from recognizer.result import Recognition

SETTINGS = ExploreSettings(touches=8, samples_per_touch=9, roll_span_rad=math.radians(30), min_touches=3,
                           recognize={"alpha": 1e-3})


def rec(cls, *rows):
    """Recognition answering ``cls`` with ranking rows (class, consistent, chi2, dof, bic)."""
    ranking = [{"class": c, "consistent": ok, "chi2": chi2, "dof": dof, "bic": bic, "p_value": 0.5}
               for c, ok, chi2, dof, bic in rows]
    return Recognition(cls, {"a": 1.0} if cls != "unclassified" else {}, ranking=ranking)


def test_runner_up_rejected_is_decisive():
    r = rec("ellipse", ("ellipse", True, 10.0, 10, 25.0), ("parabola", False, 500.0, 12, 510.0))
    assert indecision(r, None, SETTINGS) is None


def test_close_runner_up_needs_a_stable_answer():
    r = rec("parabola", ("parabola", True, 12.0, 12, 30.0), ("ellipse", True, 9.0, 10, 33.0))
    why = indecision(r, None, SETTINGS)
    assert why is not None and "parabola" in why and "ellipse" in why
    assert indecision(r, rec("ellipse", ("ellipse", True, 5.0, 6, 20.0)), SETTINGS) is not None  # changed
    assert indecision(r, rec("parabola", ("parabola", True, 5.0, 7, 18.0)), SETTINGS) is None  # stable


def test_runner_up_bic_margin():
    base = 30.0
    just = rec("circle", ("circle", True, 10.0, 14, base), ("ellipse", True, 9.0, 12, base + DECISIVE_BIC))
    below = rec("circle", ("circle", True, 10.0, 14, base), ("ellipse", True, 9.0, 12, base + DECISIVE_BIC - 0.1))
    assert indecision(just, None, SETTINGS) is None
    assert indecision(below, None, SETTINGS) is not None


def test_more_freedom_significantly_better_is_not_decisive():
    limit = stats.chi2.isf(1e-3, 2)  # the χ²_2 limit the likelihood-ratio test uses
    better = rec("circle", ("circle", True, 10.0 + limit + 0.5, 14, 20.0), ("ellipse", True, 10.0, 12, 40.0))
    assert "significantly better" in indecision(better, None, SETTINGS)
    fine = rec("circle", ("circle", True, 10.0 + limit - 0.5, 14, 20.0), ("ellipse", True, 10.0, 12, 40.0))
    assert indecision(fine, None, SETTINGS) is None


def test_final_answer_refuses_an_undecided_class():
    answers = {4: rec("parabola", ("parabola", True, 12.0, 12, 30.0), ("ellipse", True, 9.0, 10, 33.0)),
               3: rec("ellipse", ("ellipse", True, 5.0, 6, 20.0), ("parabola", True, 6.0, 7, 24.0))}
    out = final_answer(lambda touches: answers[len(touches)], [{}] * 4, SETTINGS)
    assert out.cls == "unclassified" and out.params == {}
    assert out.reason.startswith("not decisive after 4 usable touches") and "parabola" in out.reason
    assert out.ranking == answers[4].ranking
    answers[3] = rec("parabola", ("parabola", True, 5.0, 7, 18.0))
    assert final_answer(lambda touches: answers[len(touches)], [{}] * 4, SETTINGS).cls == "parabola"
