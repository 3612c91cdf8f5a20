"""Two classes that fit about equally well: the simpler (nested) class unless the richer one
is significantly better (classify.choose), a refusal naming both when neither is a limit of
the other and their BICs lie within classify.RIVAL_BIC (classify.close_rivals), and the
circle's start that lets the circle be tested at all when one κ is badly measured."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from recognizer.classify import RIVAL_BIC, close_rivals, options_for, recognize
from recognizer.contacts import Contacts
from recognizer.curves import Pose
from recognizer.result import Candidate
from recognizer.starts import starts
from recognizer.touches import parse_request

DATA = Path(__file__).parent / "data"


def _cand(cls: str, bic: float) -> Candidate:
    return Candidate(cls, {}, Pose(0.0, 0.0, 0.0), np.zeros(3), bic - 10.0, 10, 15, bic=bic)


def test_close_rivals_are_the_non_nested_classes_within_rival_bic():
    """A hyperbola answer: the cubical 3.1 below it and the semicubical 5.9 above are rivals;
    the ellipse 6.1 above is not; the parabola (a limit of the hyperbola) never is, however
    close: nested classes are the likelihood-ratio test's."""
    chosen = _cand("hyperbola", 183.0)
    others = [_cand("cubical_parabola", 179.9), _cand("semicubical_parabola", 183.0 + RIVAL_BIC - 0.1),
              _cand("ellipse", 183.0 + RIVAL_BIC + 0.1), _cand("parabola", 182.0), _cand("line", 180.0)]
    assert [c.cls for c in close_rivals(chosen, [chosen] + others)] == ["cubical_parabola", "semicubical_parabola"]
    assert close_rivals(_cand("circle", 50.0), [_cand("ellipse", 48.0), _cand("line", 51.0)]) == []


def test_circle_start_weighs_each_kappa_by_its_deviation():
    """Four contacts of a circle r = 0.4 (κ 2.5): three κ measured to ±0.3, one (a touch
    rolled across a pad's end) −31 ± 159. The plain mean of κ is negative, so the circle
    had no start and was never fitted; weighed by 1/σ², r is the good touches'."""
    t = np.array([0.0, 0.8, 1.6, 2.4])
    r = 0.4
    kappa = np.array([2.3, 2.7, -31.0, 2.6])
    sd = np.array([0.31, 0.42, 159.0, 0.31])
    cov = np.zeros((4, 2, 2))
    cov[:, 0, 0] = sd ** 2
    cov[:, 1, 1] = (100 * sd) ** 2
    d = Contacts(r * np.cos(t), r * np.sin(t), t + math.pi / 2, kappa, np.zeros(4), cov,
                 np.full(4, 1e-3), np.full(4, 1e-3))
    out = starts("circle", d)
    assert len(out) == 1
    assert out[0][0]["r"] == pytest.approx(1 / 2.5, rel=0.05)


def test_x_jaw_circle_is_answered_circle():
    """X-series jaw, bench_explore --finite 10 --anywhere --seed 61 (a development seed this
    session), circle 18 (r 22.317 mm): its four touches were answered ellipse a 22.360,
    b 22.294 (b/a 0.997), the circle absent from the ranking (no start: see above). The
    circle fits within the likelihood-ratio test's limit of the ellipse, so it is the
    answer, the ellipse named in also_fits."""
    req = parse_request(json.loads((DATA / "x_circle_61_18.json").read_text()))
    rec = recognize(req, options_for(req))
    assert rec.cls == "circle", [(r.cls, r.chi2) for r in rec.ranking]
    assert rec.params["r"] == pytest.approx(22.317, abs=3 * rec.uncertainty["r"])
    assert [a["class"] for a in rec.also_fits] == ["ellipse"]


def test_circle_started_from_a_round_ellipse(monkeypatch):
    """The same touches with no circle start at all (as before the weighted κ): the best
    ellipse's a − b lies within the likelihood-ratio test's limit of 0 by its own σ's, so
    the circle is started from it (r = √(ab)) and is the answer."""
    import recognizer.localize as localize

    own = localize.starts
    monkeypatch.setattr(localize, "starts", lambda cls, d, every_pair=False: [] if cls == "circle" else own(cls, d, every_pair))
    req = parse_request(json.loads((DATA / "x_circle_61_18.json").read_text()))
    rec = recognize(req, options_for(req))
    assert rec.cls == "circle", [(r.cls, r.chi2) for r in rec.ranking]
    assert rec.params["r"] == pytest.approx(22.317, abs=3 * rec.uncertainty["r"])


def test_line_against_every_curved_class_at_a_shared_level():
    """tools.bench_wide seed 67 (development), line trial 9 (a segment) after two suggested
    touches: the ranking below (χ², dof, BIC). The cubical's χ² is 18.1 below the line's, over
    the single likelihood-ratio test's 16.3 for 3 parameters, so it was answered cubical; the
    line is tested against five consistent curved classes at once, whose shared level
    1e-3 / 5 needs 19.7: the line is the answer, the cubical in also_fits."""
    from recognizer.classify import also_fits, choose, lr_limit

    rows = [("cubical_parabola", 91.727, 85, 336.990), ("line", 109.783, 88, 340.331),
            ("semicubical_parabola", 106.595, 85, 351.859), ("ellipse", 107.038, 85, 352.301),
            ("hyperbola", 107.768, 85, 353.031), ("parabola", 119.555, 86, 359.913)]
    cons = [Candidate(c, {}, Pose(0.0, 0.0, 0.0), np.zeros(1), x, dof, 0, loglik=-0.5 * x, bic=b) for c, x, dof, b in rows]
    chosen = choose(cons)
    assert chosen.cls == "line"
    assert lr_limit("line", "cubical_parabola", cons) == pytest.approx(19.66, abs=0.01)
    cubical = next(a for a in also_fits(chosen, cons) if a["class"] == "cubical_parabola")
    assert cubical["gain"] == pytest.approx(18.06, abs=0.01) and cubical["needed"] > cubical["gain"]
