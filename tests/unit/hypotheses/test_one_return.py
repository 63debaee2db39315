"""Murty's k best of a one-return problem without the solver (:mod:`hypotrack.hypotheses.one_return`).

Oracle: the general path (:func:`hypotrack.association.murty_k_best` on the extended matrix), taken by making the
closed form decline; the children (events, order and log-weights) must be identical, bit for bit, on rows with
seeded options, birth columns, gated-out columns, more and fewer finite entries than ``k``, and equal entries
(where the closed form must hand over to the solver). A hand-computed row fixes the order and the codes.
"""
import numpy as np
import pytest

from hypotrack.hypotheses import MurtyGenerator
from hypotrack.hypotheses import generators as gen_mod
from hypotrack.hypotheses.association_problem import AssociationProblem
from hypotrack.hypotheses.one_return import one_return_k_best


def _problem(ts, os_, n_obj, constant=-0.75, phi=0.0):
    ts, os_ = np.atleast_2d(np.asarray(ts, float)), np.atleast_2d(np.asarray(os_, float))
    return AssociationProblem(ts, os_, n_obj, np.full((n_obj + 1, ts.shape[1] - n_obj + 1), phi), constant=constant)


def _general(problem, k, monkeypatch):
    with monkeypatch.context() as m:
        m.setattr(gen_mod, "one_return_k_best", lambda p, k: None)
        return MurtyGenerator(k=k).generate(problem)


def test_hand_computed_row():
    # objects 0, 1 (1 gated out), a birth column 2; clutter -1.0; seeded components -2 (0.5), -3 (-3.0)
    p = _problem([[2.0, -np.inf, 0.25]], [[-1.0, 0.5, -3.0]], 2)
    ev, lw = one_return_k_best(p, 10)
    assert ev.dtype == np.int32 and ev.shape == (5, 1)
    assert ev[:, 0].tolist() == [0, -2, 2, -1, -3]
    assert lw.tolist() == [1.25, -0.25, -0.5, -1.75, -3.75]  # the entries plus the constant -0.75
    ev, lw = one_return_k_best(p, 3)
    assert ev[:, 0].tolist() == [0, -2, 2]
    events, lw = MurtyGenerator(k=3).generate(p)
    assert events[:, 0].tolist() == [0, -2, 2] and np.allclose(lw, np.array([2.0, 0.5, 0.25]) - 0.75, rtol=0, atol=0)


def test_ties_hand_over_to_the_solver():
    tie_top = _problem([[1.0, 1.0]], [[-2.0, 0.0]], 2)  # two equal optima: the solver's pick leads
    assert one_return_k_best(tie_top, 10) is None
    tie_below = _problem([[3.0, 1.0]], [[-2.0, 1.0]], 2)  # equal entries below a unique optimum, all kept
    ev, _ = one_return_k_best(tie_below, 10)
    assert ev[:, 0].tolist() == [0, 1, -2, -1]  # column order among the equal: object 1 before the seeded option
    assert one_return_k_best(tie_below, 2) is None  # more entries than k, a tie among the k + 1 best: the chain's
    assert one_return_k_best(tie_below, 1) is not None  # the two best distinct: no choice left to the solver


def test_malformed_rows_decline():
    assert one_return_k_best(_problem([[np.nan, 0.0]], [[-1.0]], 2), 5) is None
    assert one_return_k_best(_problem([[0.5, 0.0]], [[-np.inf, 1.0]], 2), 5) is None  # no clutter: the general error
    assert one_return_k_best(_problem([[0.5, 0.0]], [[-1.0]], 2, phi=np.inf), 5) is None
    with pytest.raises(ValueError, match="clutter"):
        MurtyGenerator(k=5).generate(_problem([[0.5, 0.0]], [[-np.inf, 1.0]], 2))


def test_an_infeasible_parent_has_no_child(monkeypatch):
    p = _problem([[0.5, 0.0]], [[-1.0, 0.2]], 2, constant=-np.inf)
    fast, ref = MurtyGenerator(k=5).generate(p), _general(p, 5, monkeypatch)
    assert fast[0].shape == ref[0].shape == (0, 1) and len(fast[1]) == len(ref[1]) == 0


@pytest.mark.parametrize("seed", range(12))
def test_equal_to_the_general_path(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(40):
        n_obj, n_birth, n_opt = int(rng.integers(0, 4)), int(rng.integers(0, 3)), int(rng.integers(1, 6))
        ts = rng.normal(size=(1, n_obj + n_birth))
        ts[rng.random(ts.shape) < 0.3] = -np.inf
        os_ = rng.normal(size=(1, n_opt))
        if rng.random() < 0.5:  # equal entries: rounded to a coarse grid
            ts, os_ = np.round(ts * 2) / 2, np.round(os_ * 2) / 2
        os_[rng.random(os_.shape) < 0.2] = -np.inf
        os_[0, 0] = rng.normal()  # clutter finite
        p = _problem(ts, os_, n_obj, constant=float(rng.normal() * 10), phi=float(rng.choice([0.0, -0.0, -1.3])))
        for k in (1, 2, 3, 20):
            fast = MurtyGenerator(k=k).generate(p)
            ref = _general(p, k, monkeypatch)
            assert fast[0].dtype == ref[0].dtype
            np.testing.assert_array_equal(fast[0], ref[0])
            assert fast[1].tobytes() == ref[1].tobytes()
            checked += 1
    assert checked == 160
