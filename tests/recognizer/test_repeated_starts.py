"""recognizer.localize: a closed-form start met again (several pairs of touches giving one
frame) is not solved again; the fits are those of every start solved (the repeat would
have solved to the same fit, which the every-start list keeps once anyway)."""

import numpy as np

from recognizer import contacts as L
from recognizer import localize
from recognizer.curves import CURVES
from recognizer.solver import ContactModel


def _touches() -> L.Contacts:
    rng = np.random.default_rng(11)
    c = CURVES["cubical_parabola"]({"a": 0.02, "c": 0.3})
    t = np.array([-4.0, 1.0, 5.0])
    x, y, phi, k, ks = c.frame(t)
    sk, sks = 1e-3, 1e-4
    return L.Contacts(x + rng.normal(0, 0.02, 3), y + rng.normal(0, 0.02, 3), phi + rng.normal(0, 1.5e-3, 3),
                      k + rng.normal(0, sk, 3), ks + rng.normal(0, sks, 3), np.tile(np.diag([sk**2, sks**2]), (3, 1, 1)),
                      np.full(3, 0.02), np.full(3, 1.5e-3))


def test_a_repeated_start_is_solved_once(monkeypatch):
    d = _touches()
    # at most 5 starts: twice over they stay within the 10 best-placed that are solved
    own = localize.starts("cubical_parabola", localize._oriented("cubical_parabola", d), every_pair=True)[:5]
    assert len(own) >= 2
    solved = []
    solve = ContactModel.solve

    def counting(self, z0, *a, **k):
        solved.append(np.array(z0, float).tobytes())
        return solve(self, z0, *a, **k)

    monkeypatch.setattr(ContactModel, "solve", counting)
    monkeypatch.setattr(localize, "starts", lambda cls, dd, every_pair=False: list(own))
    once = localize.fit_class_every_start("cubical_parabola", d)
    n_once = len(solved)
    solved.clear()
    # every start twice, as pairs that give one frame do
    monkeypatch.setattr(localize, "starts", lambda cls, dd, every_pair=False: [s for s in own for _ in (0, 1)])
    twice = localize.fit_class_every_start("cubical_parabola", d)
    assert len(solved) == n_once == len(set(solved))
    assert [f.chi2 for f in twice] == [f.chi2 for f in once]
    assert all(f.params == g.params for f, g in zip(twice, once))
