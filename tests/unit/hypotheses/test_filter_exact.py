"""The hypothesis filter and its child generators on exact oracles: hand-computed weights with
births and deaths, in-view versus out-of-view objects, brute-force enumeration, exact top-k.

The child oracle enumerates, for one parent and a scan of m = 3 returns, every association
(each return on clutter, an object or a birth region, no column twice) and every allowed
silent event (an undetected birth in an unused region, a death of an undetected object), and
weighs each child with document 000 Eq. 8 × Eq. 30 (H-FISST, single event) or document 001 Eq. 6–7 ×
Eq. 31, 59 (FISST with Poisson clutter, binomial population), written out term by term with
scipy's Gaussian densities.
"""

import copy
import itertools
import math
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.special import logsumexp
from scipy.stats import chi2, multivariate_normal

from hypotrack.association import EnumerationBudgetError
from hypotrack.hypotheses import (
    AssociationProblem,
    BinomialPopulation,
    ChildGenerator,
    ChildSet,
    ExhaustiveGenerator,
    FISSTPoissonWeights,
    HFISSTWeights,
    Hypothesis,
    HypothesisFilter,
    MCMCGenerator,
    MurtyGenerator,
    ReidWeights,
    ScanContext,
    SingleEventPopulation,
)
from hypotrack.hypotheses.children import twins_never_heavier
from hypotrack.hypotheses.generators import top_k
from hypotrack.hypotheses.state import FilterState
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from scenes import H_POSITION, position_sensor

REGION = Box([-50.0, -50.0], [50.0, 50.0])
V = 100.0 * 100.0
HALVES = [Box([-50.0, -50.0], [0.0, 50.0]), Box([0.0, -50.0], [50.0, 50.0])]
MOTION = ConstantVelocity(0.05)
H = H_POSITION
R = np.eye(2) * 0.5
# objects 0 and 1 in view, object 2 out of view (x = 60 > 50: p_D = 0)
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [4.0, 1.0, 0.0, 1.0], [60.0, 0.0, 0.0, 0.0]])
P0 = np.stack([np.diag([1.0, 1.0, 0.2, 0.2]), np.diag([0.5, 0.8, 0.1, 0.3]), np.eye(4)])
Z = np.array([[1.3, -0.2], [4.2, 1.7], [-30.0, 20.0]])  # near object 0, near object 1, in the left half


def _sensor(p_D, rate=1.0):
    return position_sensor(R, p_D, REGION, rate)


def _births():
    return [UniformBirthDensity(h, np.eye(2) * 4.0) for h in HALVES]


def oracle(model, p_D, rate=1.0, alpha=0.0, beta=0.0, p_s=1.0):
    """{(kind, arg, events): log-weight} of every child of the initial parent for scan Z."""
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    M, B, m = len(X0), len(HALVES), len(Z)
    logg, p = [], []
    for j in range(M):
        x, P = F @ X0[j], F @ P0[j] @ F.T + Q
        logg.append(multivariate_normal(H @ x, H @ P @ H.T + R).logpdf(Z))
        p.append(p_D if REGION.contains((H @ x)[None])[0] else 0.0)
    in_view = [j for j in range(M) if p[j] > 0]
    birth_g = [[-np.log(h.area) if h.contains(z[None])[0] else -np.inf for h in HALVES] for z in Z]
    out = {}
    for ev in itertools.product(range(-1, M + B), repeat=m):
        used = [c for c in ev if c >= 0]
        if len(used) != len(set(used)):
            continue
        det_obj = {c for c in used if c < M}
        det_births = [c - M for c in used if c >= M]
        silent = [None] + [("birth", r) for r in range(B) if r not in det_births]
        silent += [("death", j) for j in range(M) if j not in det_obj]
        for s in silent:
            born = det_births + ([s[1]] if s and s[0] == "birth" else [])
            dead = [s[1]] if s and s[0] == "death" else []
            if model == "single":
                if len(born) + len(dead) > 1 or (dead and dead[0] not in in_view):
                    continue
                lp = np.log(alpha) if born else np.log(beta) if dead else np.log(1 - B * alpha - len(in_view) * beta)
            else:
                lp = len(born) * np.log(alpha) + (B - len(born)) * np.log1p(-alpha)
                lp += len(dead) * np.log1p(-p_s) + (M - len(dead)) * np.log(p_s)
            lw = lp
            for j in range(M):
                if j in dead:
                    continue
                if j in det_obj:
                    i = ev.index(j)
                    lw += np.log(p[j]) + logg[j][i] if p[j] > 0 else -np.inf
                else:
                    lw += np.log1p(-p[j])
            for i, c in enumerate(ev):
                if c >= M:
                    lw += np.log(p_D) + birth_g[i][c - M]
            if s and s[0] == "birth":
                lw += np.log1p(-p_D)
            n_det, n_clutter = len(used), m - len(used)
            if model == "single":  # H-FISST: clutter density 1/V and −log(C(m, k) k!)
                lw += n_clutter * -np.log(V) - (math.lgamma(m + 1) - math.lgamma(m - n_det + 1))
            else:  # FISST, Poisson clutter: Eq. 6 × Eq. 7
                lw += -rate + n_clutter * np.log(rate) - math.lgamma(n_clutter + 1)
                lw += math.lgamma(n_clutter + 1) - n_clutter * np.log(V)
            if not np.isfinite(lw):
                continue
            kind = (ChildSet.ASSOCIATION if s is None else
                    ChildSet.UNDETECTED_BIRTH if s[0] == "birth" else ChildSet.DEATH)
            out[(kind, -1 if s is None else s[1], ev)] = lw
    return out


def _filter(model, p_D, rate=1.0, alpha=0.0, beta=0.0, p_s=1.0, max_hypotheses=10**6):
    if model == "single":
        pop = SingleEventPopulation(SingleEventBirthDeath(alpha, beta, 2), birth_densities=_births())
        weights = HFISSTWeights()
    else:
        pop = BinomialPopulation(_births(), alpha=alpha, p_survive=p_s)
        weights = FISSTPoissonWeights()
    return HypothesisFilter(MOTION, _sensor(p_D, rate), weights, ExhaustiveGenerator(), population=pop,
                            max_hypotheses=max_hypotheses, means=X0, covs=P0, seed=0)


def _by_key(ch):
    return {(int(k), int(a), tuple(int(e) for e in ev)): lw
            for k, a, ev, lw in zip(ch.kind, ch.arg, ch.events, ch.log_weights)}


CASES = [
    dict(model="single", p_D=0.8, alpha=0.01, beta=0.05),
    dict(model="single", p_D=0.99, alpha=0.01, beta=0.2),  # death twins outweigh their children
    dict(model="binomial", p_D=0.8, alpha=0.02, p_s=0.9, rate=2.0),
    dict(model="binomial", p_D=0.95, alpha=0.3, p_s=0.9, rate=0.5),
]


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c['model']}-pD{c['p_D']}")
def test_every_child_of_three_objects_and_three_returns_weighed_by_hand(case):
    want = oracle(**case)
    got = _by_key(_filter(**case).expand(Z))
    assert got.keys() == want.keys()
    for key, lw in want.items():
        assert got[key] == pytest.approx(lw, abs=1e-9), key
    # the out-of-view object (2) is never detected; it dies only under the binomial model
    assert not any(2 in ev for _, _, ev in got)
    assert any(k == ChildSet.DEATH and a == 2 for k, a, _ in got) == (case["model"] == "binomial")


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c['model']}-pD{c['p_D']}")
@pytest.mark.parametrize("keep", [1, 4, 25])
def test_kept_children_are_the_exact_top_k_and_normalised(case, keep):
    want = oracle(**case)
    f = _filter(**case, max_hypotheses=keep)
    post = f.step(Z)
    best = sorted(want.values(), reverse=True)[:keep]
    np.testing.assert_allclose(np.sort(f.last_kept.log_weights)[::-1], best, atol=1e-9)
    for key, lw in _by_key(f.last_kept).items():
        assert lw == pytest.approx(want[key], abs=1e-9), key
    np.testing.assert_allclose(post.log_weights, np.array(best) - logsumexp(best), atol=1e-9)
    st = f.last_stats
    assert st["n_parents"] == 1 and st["n_kept"] == keep
    assert st["mass_retained"] == pytest.approx(np.exp(logsumexp(best) - st["log_mass_generated"]), rel=1e-9)
    assert 0 < st["mass_retained"] <= 1


@pytest.mark.parametrize("case", CASES[1:3], ids=lambda c: f"{c['model']}-pD{c['p_D']}")
def test_stats_of_an_uncapped_step_count_every_child(case):
    want = oracle(**case)
    f = _filter(**case)
    f.step(Z)
    st = f.last_stats
    n_assoc = sum(k[0] == ChildSet.ASSOCIATION for k in want)
    assert st["n_association_children"] == n_assoc
    assert st["n_twin_children"] == len(want) - n_assoc
    assert st["n_kept"] == len(want)
    assert st["log_mass_generated"] == pytest.approx(logsumexp(list(want.values())), abs=1e-9)
    assert st["mass_retained"] == pytest.approx(1.0, abs=1e-12)


def test_top_k_is_stable_beyond_insertion_sort_sizes():
    lw = np.log(np.random.default_rng(3).choice([0.1, 0.2, 0.3, 0.4], size=300))
    stable = sorted(range(300), key=lambda i: (-lw[i], i))
    np.testing.assert_array_equal(top_k(lw, None), stable)
    for k in (1, 40, 120, 299, 300):
        sel = top_k(lw, k)
        np.testing.assert_array_equal(lw[sel], lw[stable[:k]])  # the k largest, best first
        assert len(set(sel.tolist())) == k


def test_top_k_is_the_k_largest_best_first_with_stable_ties():
    lw = np.array([0.5, 2.0, -1.0, 2.0, 0.5, 3.0])
    np.testing.assert_array_equal(top_k(lw, 3), [5, 1, 3])
    np.testing.assert_array_equal(top_k(lw, None), [5, 1, 3, 0, 4, 2])
    np.testing.assert_array_equal(top_k(lw, 6), [5, 1, 3, 0, 4, 2])
    np.testing.assert_array_equal(top_k(lw, 1), [5])
    np.testing.assert_array_equal(top_k(lw, 5), [5, 1, 3, 0, 4])


def test_top_k_of_distinct_weights_for_every_k():
    """Every k from 1 to n on distinct weights: exactly the k largest, best first (n up to 1000,
    past the sizes where NumPy's selection is a plain insertion sort)."""
    rng = np.random.default_rng(11)
    for n in (2, 5, 17, 64, 300, 1000):
        for _ in range(5):
            lw = rng.normal(size=n)
            order = np.argsort(-lw)
            for k in (range(1, n + 1) if n < 100 else (1, 2, 3, n // 2, n - 1, n)):
                np.testing.assert_array_equal(top_k(lw, k), order[:k])


# ---------------------------------------------------------------- child generators on brute force
def brute_force(problem):
    """{event: constant + Σ_i score[i, a_i] + φ[k, b]} over every feasible event."""
    C, T, m, n = problem.n_exclusive, problem.n_options, problem.n_returns, problem.n_objects
    out = {}
    for a in itertools.product([*range(C), *(-1 - t for t in range(T))], repeat=m):
        excl = [x for x in a if x >= 0]
        if len(set(excl)) != len(excl):
            continue
        k = sum(x < n for x in excl)
        w = problem.constant + problem.count_term[k, len(excl) - k]
        w += sum(problem.target_scores[i, x] if x >= 0 else problem.option_scores[i, -1 - x] for i, x in enumerate(a))
        if np.isfinite(w):
            out[a] = w
    return out


def _random_problem(seed, m=4, n_obj=3, n_birth=1, n_opt=1, constant_phi=False, gated=0.25):
    rng = np.random.default_rng(seed)
    target = rng.normal(scale=2.0, size=(m, n_obj + n_birth))
    target[rng.random(target.shape) < gated] = -np.inf
    options = rng.normal(size=(m, n_opt))
    phi = np.full((n_obj + 1, n_birth + 1), -0.3) if constant_phi else rng.normal(size=(n_obj + 1, n_birth + 1))
    return AssociationProblem(target, options, n_obj, phi, constant=float(rng.normal()))


def _as_dict(ev, lw):
    return {tuple(int(x) for x in e): w for e, w in zip(ev, lw)}


def _assert_top(ev, lw, oracle, k):
    best = sorted(oracle.values(), reverse=True)[:k]
    assert ev.dtype == np.int32 and ev.shape == (len(best), next(iter(oracle)).__len__())
    np.testing.assert_allclose(lw, best, atol=1e-10)  # best first, exactly the top k
    for e, w in _as_dict(ev, lw).items():
        assert w == pytest.approx(oracle[e], abs=1e-10)


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("n_opt", [1, 2])
def test_exhaustive_generator_streams_the_exact_top_k(seed, n_opt):
    problem = _random_problem(seed, n_opt=n_opt)
    oracle = brute_force(problem)
    ev, lw = ExhaustiveGenerator().generate(problem)
    assert _as_dict(ev, lw).keys() == oracle.keys() and ev.dtype == np.int32
    for keep in (1, 5, 17):
        ev, lw = ExhaustiveGenerator(chunk_size=7).generate(problem, keep=keep)
        _assert_top(ev, lw, oracle, keep)
    ev, lw = ExhaustiveGenerator(chunk_size=7).generate(problem, keep=10**6)
    assert _as_dict(ev, lw).keys() == oracle.keys()


def test_exhaustive_generator_budget_and_empty_scan():
    problem = _random_problem(0, m=4, n_obj=3, n_birth=1, gated=0.0)
    n = len(brute_force(problem))
    assert ExhaustiveGenerator(max_events=n).generate(problem)[0].shape == (n, 4)
    assert ExhaustiveGenerator(max_events=n).generate(problem, keep=3)[0].shape == (3, 4)
    with pytest.raises(EnumerationBudgetError, match=f"^enumeration would produce {n:,} association events, "
                                                     f"exceeding max_events={n - 1:,}; "):
        ExhaustiveGenerator(max_events=n - 1).generate(problem)
    with pytest.raises(EnumerationBudgetError, match=f"^enumeration would produce more than {n - 1:,} association "
                                                     f"events, exceeding max_events={n - 1:,}; ") as err:
        ExhaustiveGenerator(max_events=n - 1).generate(problem, keep=3)  # streaming: counting stops at the budget
    assert err.value.budget == n - 1 and err.value.count > n - 1
    ev1, lw1 = ExhaustiveGenerator(chunk_size=1).generate(problem, keep=5)  # one event per chunk
    ev2, lw2 = ExhaustiveGenerator().generate(problem, keep=5)
    np.testing.assert_array_equal(ev1, ev2)
    np.testing.assert_array_equal(lw1, lw2)
    empty = AssociationProblem(np.zeros((0, 2)), np.zeros((0, 1)), 2, np.full((3, 1), -0.5), constant=1.5)
    for gen in (ExhaustiveGenerator(), MurtyGenerator(k=3), MCMCGenerator(n_steps=10)):
        ev, lw = gen.generate(empty, np.random.default_rng(0), keep=2)
        assert ev.shape == (1, 0) and ev.dtype == np.int32
        np.testing.assert_array_equal(lw, [1.0])  # constant + φ[0, 0]
    for bad in (dict(max_events=0), dict(chunk_size=0)):
        with pytest.raises(ValueError, match=rf"^{next(iter(bad))} must be an integer in \[1, inf\], got 0$"):
            ExhaustiveGenerator(**bad)


@pytest.mark.parametrize("seed", range(3))
@pytest.mark.parametrize("n_opt, constant_phi", [(1, True), (1, False), (2, True), (2, False)])
def test_murty_generator_returns_the_exact_top_k(seed, n_opt, constant_phi):
    problem = _random_problem(seed + 10, n_opt=n_opt, constant_phi=constant_phi)
    oracle = brute_force(problem)
    for k, keep in ((1, None), (6, None), (9, 4), (4, 9)):
        ev, lw = MurtyGenerator(k=k).generate(problem, keep=keep)
        _assert_top(ev, lw, oracle, min(k, keep or k))
    if n_opt == 1:  # blocks of equal counts (polynomial): exact whatever the ranking budget
        ev, lw = MurtyGenerator(k=6, max_solutions=6).generate(problem)
        _assert_top(ev, lw, oracle, 6)
    ev, lw = MurtyGenerator(k=10**4).generate(problem)  # more than exist: every event
    assert _as_dict(ev, lw).keys() == oracle.keys()


def test_murty_generator_when_every_count_is_forbidden():
    forbidden = AssociationProblem(np.zeros((2, 2)), np.zeros((2, 2)), 1, np.full((2, 2), -np.inf))
    ev, lw = MurtyGenerator(k=3, max_solutions=50).generate(forbidden)
    assert ev.shape == (0, 2) and lw.shape == (0,)


def test_murty_generator_budget_returns_the_best_found():
    problem = _random_problem(3, n_opt=2, constant_phi=False)
    oracle = brute_force(problem)
    ev, lw = MurtyGenerator(k=5, max_solutions=5).generate(problem)
    assert len(lw) <= 5 and np.all(np.diff(lw) <= 0)
    for e, w in _as_dict(ev, lw).items():
        assert w == pytest.approx(oracle[e], abs=1e-10)
    for bad in (dict(k=0), dict(max_solutions=0)):
        with pytest.raises(ValueError, match=rf"^{next(iter(bad))} must be an integer in \[1, inf\], got 0$"):
            MurtyGenerator(**bad)
    assert MurtyGenerator(k=1, max_solutions=1).max_solutions == 1


@pytest.mark.parametrize("seed", range(3))
def test_murty_generator_grows_past_events_the_count_term_forbids(seed):
    """Seeded births and a count term that forbids exactly one detected object: the best
    separable events are often infeasible, and the k-best list grows until k feasible ones are proven."""
    base = _random_problem(seed + 20, m=4, n_obj=3, n_birth=1, n_opt=2)
    phi = base.count_term.copy()
    phi[1, :] = -np.inf
    problem = AssociationProblem(base.target_scores, base.option_scores, 3, phi, constant=base.constant)
    oracle = brute_force(problem)
    for k in (1, 3, 8):
        ev, lw = MurtyGenerator(k=k).generate(problem)
        _assert_top(ev, lw, oracle, k)


@pytest.mark.parametrize("init", ["random", "clutter", "best"])
def test_mcmc_generator_finds_every_child_with_exact_weights(init):
    problem = _random_problem(5, m=3, n_obj=2, n_birth=1, n_opt=2)
    oracle = brute_force(problem)
    gen = MCMCGenerator(n_steps=4000, init=init, completion_rounds=0)
    ev, lw = gen.generate(problem, np.random.default_rng(2))
    got = _as_dict(ev, lw)
    total = logsumexp(list(oracle.values()))
    heavy = {e for e, w in oracle.items() if w >= total + np.log(1e-2)}
    assert heavy <= got.keys() <= oracle.keys() and len(heavy) >= 15  # the chain alone finds the heavy ones
    completed = MCMCGenerator(n_steps=4000, init=init).generate(problem, np.random.default_rng(2))
    assert _as_dict(*completed).keys() == oracle.keys()  # the neighbour completion finds the rest
    for e, w in got.items():
        assert w == pytest.approx(oracle[e], abs=1e-10)
    ev, lw = gen.generate(problem, np.random.default_rng(2), keep=3)
    _assert_top(np.asarray(ev, np.int32), lw, {e: oracle[e] for e in got}, 3)
    ev2, lw2 = gen.generate(problem, np.random.default_rng(2), keep=3)
    np.testing.assert_array_equal(ev2, ev)


@pytest.mark.parametrize("kwargs, match", [
    (dict(n_steps=0), r"n_steps must be an integer in \[1, inf\], got 0"),
    (dict(n_steps=10, burn_in=11), r"burn_in must be an integer in \[0, 10\], got 11"),
    (dict(burn_in=-1), r"burn_in must be an integer in \[0, 100000\], got -1"),
    (dict(variant="metropolis"), r"variant must be one of \('paper', 'symmetric', 'gibbs'\), got 'metropolis'"),
    (dict(temperature=0.0), r"temperature must be a finite number > 0, got 0.0"),
    (dict(completion_rounds=-1), r"completion_rounds must be an integer in \[0, inf\], got -1"),
    (dict(completion_threshold=1.0), r"completion_threshold must lie in \(0, 1\), got 1.0"),
    (dict(completion_threshold=0.0), r"completion_threshold must lie in \(0, 1\), got 0.0"),
    (dict(init="greedy"), r"init must be 'random', 'clutter' or 'best', got 'greedy'"),
])
def test_mcmc_generator_options_are_checked(kwargs, match):
    with pytest.raises(ValueError, match=match):
        MCMCGenerator(**kwargs)


# ---------------------------------------------------------------- the step's new hypotheses
def _kalman(x, P, z):
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    A = np.eye(4) - K @ H
    return x + K @ (z - H @ x), A @ P @ A.T + K @ R @ K.T


@pytest.mark.parametrize("case", [CASES[0], CASES[2]], ids=["single", "binomial"])
def test_kept_hypotheses_hold_the_updated_surviving_and_newborn_tracks(case):
    f = _filter(**case)
    f.step(Z)
    kept, store, F, Q = f.last_kept, f.store, MOTION.F(1.0), MOTION.Q(1.0)
    pred = [(F @ X0[j], F @ P0[j] @ F.T + Q) for j in range(3)]
    births, pop = _births(), f.population
    label_of, pairs = {}, set()
    for c, tracks in enumerate(f.track_lists):
        ev, kind, arg = kept.events[c], int(kept.kind[c]), int(kept.arg[c])
        dead = [arg] if kind == ChildSet.DEATH else []
        want = []
        for j in range(3):
            if j in dead:
                continue
            hit = np.flatnonzero(ev == j)
            want.append(((j, int(hit[0])) if len(hit) else (j, -1),
                         _kalman(*pred[j], Z[hit[0]]) if len(hit) else pred[j]))
            if len(hit):
                pairs.add((j, int(hit[0])))
        for i in np.flatnonzero(ev >= 3):
            want.append((("born", int(ev[i]) - 3, int(i)), births[ev[i] - 3].initial_state(Z[i], R)))
        if kind == ChildSet.UNDETECTED_BIRTH:
            want.append((("born", arg, -1), pop.birth_track(arg, None, R)))
        assert len(tracks) == len(want)
        for t, (key, (mean, cov)) in zip(tracks, want):
            np.testing.assert_allclose(store.means[t], mean, atol=1e-10)
            np.testing.assert_allclose(store.covs[t], cov, atol=1e-10)
            if key[0] != "born":
                assert store.labels[t] == key[0]  # an object keeps its label through updates
            else:
                assert store.labels[t] >= 3 and label_of.setdefault(key, store.labels[t]) == store.labels[t]
        assert f.hypotheses[c].tracks == tuple(int(t) for t in tracks)
        assert f.hypotheses[c].log_weight == pytest.approx(f.log_weights[c])
        assert f.lineage_keys[c] == ((), kind, arg, ev.tobytes())
    assert len(set(label_of.values())) == len(label_of)  # one fresh label per newborn track
    assert f.last_stats["n_kalman_updates"] == len(pairs)
    assert f.scan_index == 1 and f.next_label == 3 + len(label_of)
    np.testing.assert_allclose(f.estimates().x, store.means[f.track_lists[int(np.argmax(f.log_weights))]])
    assert len(f.posterior(n_top=2).top) == 2 and len(f.posterior().top) == min(10, len(kept))


# ---------------------------------------------------------------- construction, state, messages
def test_filter_construction_messages_name_the_argument():
    s = _sensor(0.8)
    with pytest.raises(TypeError, match=r"^weights must be a WeightModel, got str$"):
        HypothesisFilter(MOTION, s, "hfisst", ExhaustiveGenerator())
    with pytest.raises(TypeError, match=r"^generator must be a ChildGenerator, got str$"):
        HypothesisFilter(MOTION, s, HFISSTWeights(), "exhaustive")
    no_clutter = Sensor(LinearPositionSensor(R, 4), DetectionModel(0.8, REGION))
    with pytest.raises(ValueError, match=r"^sensor.clutter must be a PoissonClutter: its region's area is the "
                                         r"clutter volume V$"):
        HypothesisFilter(MOTION, no_clutter, HFISSTWeights(), ExhaustiveGenerator())
    for p_D in (1.0,):  # the sensor allows p_D = 1; the filter needs a possible miss
        with pytest.raises(ValueError, match=r"^p_D must lie in \(0, 1\), got .*: hypothesis weights hold "
                                             r"log\(1 - p_D\) for every missed object$"):
            HypothesisFilter(MOTION, _sensor(p_D), HFISSTWeights(), ExhaustiveGenerator())
    reid = ReidWeights(birth_intensity=1e-3, birth_density=_births()[0])
    with pytest.raises(ValueError, match=r"^HOMHT's seeded births and population birth regions are two birth "
                                         r"models; use one$"):
        HypothesisFilter(MOTION, s, reid, ExhaustiveGenerator(), population=BinomialPopulation(_births(), alpha=0.1))
    HypothesisFilter(MOTION, s, reid, ExhaustiveGenerator(), population=BinomialPopulation([], p_survive=0.9))
    HypothesisFilter(MOTION, s, ReidWeights(), ExhaustiveGenerator(), population=BinomialPopulation(_births()))
    with pytest.raises(ValueError, match=r"^cap must be 'top' or 'sample', got 'best'$"):
        HypothesisFilter(MOTION, s, HFISSTWeights(), ExhaustiveGenerator(), cap="best")
    for kw, match in ((dict(dt=0.0), r"^dt must be a finite number > 0, got 0.0$"),
                      (dict(max_hypotheses=0), r"^max_hypotheses must be an integer in \[1, inf\], got 0$"),
                      (dict(gate_probability=1.0), r"^gate_probability must lie in \(0, 1\), got 1.0$"),
                      (dict(gate_probability=0.0), r"^gate_probability must lie in \(0, 1\), got 0.0$"),
                      (dict(means=X0), r"^covs are required with means$"),
                      (dict(means=X0[:, :3], covs=P0), r"^means must have shape \(n, 4\), got \(3, 3\)$")):
        with pytest.raises(ValueError, match=match):
            HypothesisFilter(MOTION, s, HFISSTWeights(), ExhaustiveGenerator(), **kw)
    with pytest.raises(ValueError, match=r"^the motion model's states are 4-dimensional but the sensor \(H of "
                                         r"shape \(2, 6\)\) expects 6-dimensional states$"):
        HypothesisFilter(MOTION, position_sensor(R, 0.8, REGION, 1.0, ndim_state=6), HFISSTWeights(),
                         ExhaustiveGenerator())
    f = HypothesisFilter(MOTION, s, HFISSTWeights(), ExhaustiveGenerator(), means=X0, covs=P0)
    for bad, match in ((np.zeros((1, 3)), r"^Z must have shape \(m, 2\), got \(1, 3\)$"), ([[np.nan, 0.0]], "^Z must")):
        with pytest.raises(ValueError, match=match):
            f.step(bad)
    with pytest.raises(ValueError, match=r"^dt must be a finite number >= 0, got -1.0$"):
        f.step(Z, dt=-1.0)
    with pytest.raises(ValueError, match=r"^dt must be a finite number >= 0, got -0.5$"):
        f.expand(Z, dt=-0.5)
    with pytest.raises(ValueError, match=r"^time must be >= the filter's time 0.0 \(scans in order\), got -1.0$"):
        f.step(Z, -1.0)
    with pytest.raises(ValueError, match=r"^give the scan's time or its interval dt, not both"):
        f.step(Z, 1.0, dt=1.0)


def test_filter_state_accessors_and_initialisation():
    g = np.random.default_rng(5)
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), seed=g, dt=0.5,
                         max_hypotheses=7, gate_probability=0.95, means=X0[:2], covs=P0[:2], labels=[5, 2])
    assert f.rng is g and f.dt == 0.5 and f.max_hypotheses == 7 and f.gate_probability == 0.95 and f.p_D == 0.8
    assert f.scan_index == 0 and f.last_kept is None and f.lineage_keys == [()] and f.last_stats == {}
    np.testing.assert_array_equal(f.store.labels, [5, 2])
    assert f.next_label == 6
    assert f.hypotheses == [Hypothesis(0.0, (0, 1))]
    lw, lists, keys = f.log_weights, f.track_lists, f.lineage_keys
    lw[0], lists[0][0] = 5.0, 9
    keys.append("x")
    assert f.log_weights[0] == 0.0 and f.track_lists[0][0] == 0 and f.lineage_keys == [()]  # copies
    empty = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator())
    assert len(empty.store) == 0 and empty.store.ndim == 4 and empty.hypotheses == [Hypothesis(0.0, ())]
    assert empty.next_label == 0 and empty.posterior().expected_number == 0.0
    np.testing.assert_array_equal(empty.store.labels, np.zeros(0))
    assert empty.gate_probability is None
    again = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), means=np.zeros((0, 4)))
    assert len(again.store) == 0


def test_expand_and_step_use_their_dt():
    """A scan at dt = 3 predicts with F(3): the detection child's weight uses N(z; H F(3) x, S(3))."""
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), means=X0[:1], covs=P0[:1],
                         dt=2.0)
    z = np.array([[3.2, 0.1]])
    for dt in (None, 3.0):
        t = 2.0 if dt is None else dt
        F, Q = MOTION.F(t), MOTION.Q(t)
        x, P = F @ X0[0], F @ P0[0] @ F.T + Q
        want = np.log(0.8) + multivariate_normal(H @ x, H @ P @ H.T + R).logpdf(z[0]) - np.log(1)  # C(1,1) 1! = 1
        ch = f.expand(z, dt=dt)
        assert _by_key(ch)[(0, -1, (0,))] == pytest.approx(want, abs=1e-10)
        g = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), means=X0[:1],
                             covs=P0[:1], dt=2.0)
        g.step(z, dt=dt)
        np.testing.assert_allclose(g.store.means[g.track_lists[int(np.argmax(g.log_weights))]][0],
                                   _kalman_t(x, P, z[0]), atol=1e-10)


def _kalman_t(x, P, z):
    return _kalman(x, P, z)[0]


def test_gating_removes_exactly_the_pairs_outside_the_chi2_gate():
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), means=X0[:2], covs=P0[:2],
                         gate_probability=0.9)
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    ok = np.zeros((3, 2), dtype=bool)
    for j in range(2):
        x, P = F @ X0[j], F @ P0[j] @ F.T + Q
        S = H @ P @ H.T + R
        d = Z - H @ x
        ok[:, j] = np.einsum("ij,jk,ik->i", d, np.linalg.inv(S), d) <= chi2.ppf(0.9, 2)
    assert ok.sum() == 2  # each object's own return only
    got = _by_key(f.expand(Z))
    for _, _, ev in got:
        assert all(c < 0 or ok[i, c] for i, c in enumerate(ev))
    assert len(got) == 4  # clutter or own return for each of the two objects


def test_a_failed_step_raises_and_leaves_the_filter_as_before():
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), MCMCGenerator(n_steps=50), means=X0[:2],
                         covs=P0[:2], seed=4)
    before = f.rng.bit_generator.state
    with pytest.raises(ValueError, match="Z"):
        f.step(np.zeros((2, 5)))
    assert f.rng.bit_generator.state == before and f.scan_index == 0


def test_sampled_cap_draws_without_replacement_in_proportion_to_weight():
    case = CASES[3]  # the two heaviest children hold 54 % and 33 % of the mass
    want = oracle(**case)
    keys = list(want)
    p = np.exp(np.array([want[k] for k in keys]) - logsumexp(list(want.values())))
    counts = dict.fromkeys(keys, 0)
    n = 150
    for seed in range(n):
        f = _filter(**case, max_hypotheses=1)
        f.cap = "sample"
        f.rng = np.random.default_rng(seed)
        f.step(Z)
        (key,) = _by_key(f.last_kept)
        counts[key] += 1
        assert f.log_weights[0] == 0.0
    for i in np.argsort(-p)[:2]:
        assert counts[keys[i]] / n == pytest.approx(p[i], abs=4 * np.sqrt(p[i] * (1 - p[i]) / n))


def test_sampled_cap_keeps_each_kind_of_child_at_its_share_of_the_mass():
    """Keeping one child by Gumbel-top-1 draws it with probability weight / total, whatever its
    kind. Binomial case: association children hold 87.6 % of the mass, undetected-birth twins
    2.6 %, death twins 9.8 % (oracle above). Over 1500 seeded draws each kind's frequency is within
    4 standard errors of its share; keys without the Gumbel noise for one kind of twin (or the
    noise subtracted) move a share by 8 or more standard errors."""
    case = CASES[3]
    want = oracle(**case)
    lw = np.array(list(want.values()))
    kinds = np.array([k for k, _, _ in want])
    share = {k: float(np.exp(logsumexp(lw[kinds == k]) - logsumexp(lw)))
             for k in (ChildSet.ASSOCIATION, ChildSet.UNDETECTED_BIRTH, ChildSet.DEATH)}
    assert 0.02 < share[ChildSet.UNDETECTED_BIRTH] < 0.03 and 0.09 < share[ChildSet.DEATH] < 0.11
    n = 1500
    counts = dict.fromkeys(share, 0)
    for seed in range(n):
        f = _filter(**case, max_hypotheses=1)
        f.cap = "sample"
        f.rng = np.random.default_rng(seed)
        f.step(Z)
        counts[int(f.last_kept.kind[0])] += 1
    for kind, p in share.items():
        assert counts[kind] / n == pytest.approx(p, abs=4 * np.sqrt(p * (1 - p) / n)), (kind, counts)


def test_mcmc_default_burn_in_is_a_tenth_of_the_steps():
    problem = _random_problem(5, m=3, n_obj=2, n_birth=1, n_opt=2)

    def run(**kw):
        ev, lw = MCMCGenerator(completion_rounds=0, init="clutter", **kw).generate(problem, np.random.default_rng(1))
        return _as_dict(ev, lw)

    default = run(n_steps=55)
    assert default == run(n_steps=55, burn_in=5)  # 55 // 10
    assert default != run(n_steps=55, burn_in=6)
    assert len(run(n_steps=50, burn_in=50)) < len(run(n_steps=50))  # burn-in takes steps out of the record


def test_mcmc_starting_events():
    """``init``: the paper's random permutation of columns (a return keeps its column if it is an
    allowed exclusive one, else clutter), all clutter, or the best separable assignment; an
    infeasible start falls back to all clutter."""
    problem = _random_problem(7, m=4, n_obj=3, n_birth=1, n_opt=1, constant_phi=True)
    C = problem.n_exclusive
    for seed in range(5):
        perm = np.random.default_rng(seed).permutation(C + 1)[:4]
        want = [int(c) if c < C and np.isfinite(problem.target_scores[i, c]) else -1 for i, c in enumerate(perm)]
        got = MCMCGenerator(init="random")._initial_event(problem, np.random.default_rng(seed))
        np.testing.assert_array_equal(got, want)
        assert got.dtype == np.int64
    np.testing.assert_array_equal(MCMCGenerator(init="clutter")._initial_event(problem, None), [-1] * 4)
    oracle = brute_force(problem)
    best = max(oracle, key=oracle.get)
    np.testing.assert_array_equal(MCMCGenerator(init="best")._initial_event(problem, None), best)
    seeded = _random_problem(8, m=3, n_obj=1, n_birth=0, n_opt=2, constant_phi=True)
    oracle = brute_force(seeded)
    np.testing.assert_array_equal(MCMCGenerator(init="best")._initial_event(seeded, None), max(oracle, key=oracle.get))
    forbidding = AssociationProblem(problem.target_scores, problem.option_scores, 3,
                                    np.where(np.arange(4)[:, None] == 0, 0.0, -np.inf) * np.ones((4, 2)))
    for init in ("random", "best"):  # every detection forbidden by φ: the start is all clutter
        np.testing.assert_array_equal(MCMCGenerator(init=init)._initial_event(forbidding, np.random.default_rng(0)),
                                      [-1] * 4)


def _twin_check(model, p_D, alpha=0.0, beta=0.0, p_s=1.0, p_view=(True, True, False)):
    if model == "single":
        pop = SingleEventPopulation(SingleEventBirthDeath(alpha, beta, 2), birth_densities=_births())
    else:
        pop = BinomialPopulation(_births(), alpha=alpha, p_survive=p_s)
    in_view = np.array(p_view)
    p = np.where(in_view, p_D, 0.0)
    ctx = ScanContext(Z=Z, loglik=np.zeros((3, 3)), allowed=np.ones((3, 3), bool), p_detect=p,
                      birth_loglik=np.zeros((3, 2)), p_detect_birth=p_D, clutter_rate=1.0, clutter_volume=V)
    return twins_never_heavier(pop, ctx, p, in_view)


@pytest.mark.parametrize("case, exact", [
    # single event, M_b = 2 regions, M_d = 2 objects in view: P(none) = 1 − 2α − 2β
    (dict(model="single", p_D=0.8, alpha=0.01, beta=0.05), True),  # birth log-ratio −4.5 − 1.6, death −2.9 + 1.6
    (dict(model="single", p_D=0.8, alpha=0.28, beta=0.01), True),  # birth twin log(0.28/0.42) + log 0.2 = −2.0
    (dict(model="single", p_D=0.1, alpha=0.35, beta=0.01), False),  # birth twin log(0.35/0.28) + log 0.9 = +0.12
    (dict(model="single", p_D=0.7, alpha=0.01, beta=0.2), False),  # death twin log(0.2/0.58) − log 0.3 = +0.14
    (dict(model="single", p_D=0.99, alpha=0.01, beta=0.2), False),  # the reported case: death twin +3.5
    (dict(model="single", p_D=0.4, alpha=0.01, beta=0.2), True),  # death twin log(0.2/0.58) − log 0.6 = −0.55
    (dict(model="binomial", p_D=0.3, alpha=0.02, p_s=0.5), False),  # death twin log(1) − log 0.7 = +0.36
    (dict(model="binomial", p_D=0.9, alpha=0.5, p_s=0.99), True),  # birth twin log(1) + log 0.1, death −4.6 + 2.3
    (dict(model="binomial", p_D=0.5, alpha=0.7, p_s=0.99), False),  # birth twin log(7/3) + log 0.5 = +0.15
])
def test_pretrim_is_allowed_exactly_when_no_twin_can_outweigh_its_child(case, exact):
    assert _twin_check(**case) is exact


def test_pretrim_with_every_object_out_of_view():
    out = (False, False, False)
    # no single-event death out of view; the birth twin log(0.01/0.98) + log 0.01 < 0
    assert _twin_check("single", 0.99, alpha=0.01, beta=0.2, p_view=out) is True
    # with M_d = 0, P(none) = 1 − 2α: the birth twin log(0.35/0.3) + log 0.9 = +0.05
    assert _twin_check("single", 0.1, alpha=0.35, beta=0.01, p_view=out) is False
    # binomial deaths out of view remove no miss factor: log(0.5/0.5) − log 1 = 0, a tie
    assert _twin_check("binomial", 0.3, alpha=0.02, p_s=0.5, p_view=out) is True
    assert _twin_check("binomial", 0.3, alpha=0.02, p_s=0.4, p_view=out) is False


def test_a_capped_step_asks_the_generator_only_for_the_best_when_that_is_exact():
    for case, exact in ((CASES[0], True), (dict(model="single", p_D=0.8, alpha=0.28, beta=0.01), True),
                        (CASES[1], False)):
        f = _filter(**case, max_hypotheses=3)
        f.step(Z)
        n_assoc = sum(k[0] == ChildSet.ASSOCIATION for k in oracle(**case))
        assert f.last_stats["n_association_children"] == (3 if exact else n_assoc)


class _NoChildren(ChildGenerator):
    """A generator that finds nothing (every event forbidden)."""

    def generate(self, problem, rng=None, keep=None):
        return np.zeros((0, problem.n_returns), dtype=np.int32), np.zeros(0)


def test_a_scan_without_any_child_is_refused_and_changes_nothing():
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), _NoChildren(), means=X0, covs=P0)
    ch = f.expand(Z)
    assert len(ch) == 0 and ch.events.shape == (0, 3)
    with pytest.raises(RuntimeError, match=r"^no child hypothesis has a positive weight \(every event was gated "
                                           r"out or forbidden\)$"):
        f.step(Z)
    assert f.scan_index == 0 and f.hypotheses == [Hypothesis(0.0, (0, 1, 2))]
    with pytest.raises(ValueError, match=r"^Z must have shape \(m, 2\), got \(3, 3\)$"):
        f.expand(np.zeros((3, 3)))


def test_capped_twins_keep_the_best_of_each_kind_with_integer_codes():
    f = _filter(**CASES[1], max_hypotheses=3)  # death twins can outweigh: no pre-trim
    f.step(Z)
    # per parent: the best 3 association children, the best 3 undetected-birth and 3 death twins
    assert f.last_stats["n_twin_children"] == 6
    assert f.last_kept.arg.dtype == np.int64 and f.last_kept.kind.dtype == np.int64


def test_seeded_births_start_new_tracks_at_their_returns():
    """HOMHT: a return taken by the seeded-birth option starts a track from that return
    (``birth_density.initial_state``), one fresh label per (return) shared by the hypotheses."""
    birth = _births()[1]
    f = HypothesisFilter(MOTION, _sensor(0.8), ReidWeights(birth_intensity=1e-3, birth_density=birth),
                         ExhaustiveGenerator(), means=X0[:1], covs=P0[:1], labels=[7])
    f.step(Z)
    F, Q = MOTION.F(1.0), MOTION.Q(1.0)
    pred = (F @ X0[0], F @ P0[0] @ F.T + Q)
    kept, store, seen = f.last_kept, f.store, {}
    assert any((ev == -2).any() for ev in kept.events)
    for c, tracks in enumerate(f.track_lists):
        ev = kept.events[c]
        hit = np.flatnonzero(ev == 0)
        want = [_kalman(*pred, Z[hit[0]]) if len(hit) else pred]
        want += [birth.initial_state(Z[i], R) for i in np.flatnonzero(ev == -2)]
        assert len(tracks) == len(want)
        for t, (mean, cov) in zip(tracks, want):
            np.testing.assert_allclose(store.means[t], mean, atol=1e-10)
            np.testing.assert_allclose(store.covs[t], cov, atol=1e-10)
        assert store.labels[tracks[0]] == 7
        for t, i in zip(tracks[1:], np.flatnonzero(ev == -2)):
            assert store.labels[t] >= 8 and seen.setdefault(int(i), store.labels[t]) == store.labels[t]
    assert sorted(seen.values()) == list(range(8, 8 + len(seen)))


def test_second_scan_expands_every_kept_parent():
    f = _filter(**CASES[0], max_hypotheses=4)
    f.step(Z)
    parents, keys1 = f.log_weights, f.lineage_keys
    Z2 = Z + np.array([1.0, 0.0])
    ch = f.expand(Z2)
    np.testing.assert_array_equal(np.unique(ch.parent), np.arange(4))
    for h in range(4):  # parent h alone, at its weight, has exactly its children
        alone = copy.copy(f)
        alone.state = FilterState(f.store, parents[h:h + 1], [f.track_lists[h]], [keys1[h]], f.next_label)
        mine = alone.expand(Z2)
        np.testing.assert_array_equal(mine.events, ch.events[ch.parent == h])
        np.testing.assert_allclose(mine.log_weights, ch.log_weights[ch.parent == h], rtol=0, atol=1e-12)
    uncapped = copy.copy(f)
    uncapped.max_hypotheses = 10**6  # every child of every parent counted
    uncapped.step(Z2)
    st = uncapped.last_stats
    assert st["n_association_children"] == int(np.sum(ch.kind == ChildSet.ASSOCIATION))
    assert st["n_twin_children"] == int(np.sum(ch.kind != ChildSet.ASSOCIATION))
    assert st["log_mass_generated"] == pytest.approx(logsumexp(ch.log_weights), abs=1e-10)
    f.step(Z2)
    st = f.last_stats
    assert st["n_parents"] == 4 and st["n_kept"] == 4 and f.scan_index == 2
    assert 600.0 > st["time_total"] >= st["time_generate"] >= 0.0  # seconds of this step, not a clock reading
    for c, key in enumerate(f.lineage_keys):
        assert key[0] == keys1[f.last_kept.parent[c]] and key[3] == f.last_kept.events[c].tobytes()


def test_duck_typed_sensors_are_checked_by_name_and_defaults():
    meas = LinearPositionSensor(R, 4)
    no_clutter = SimpleNamespace(measurement=meas, detection=DetectionModel(0.8, REGION))
    with pytest.raises(ValueError, match=r"^sensor.clutter must be a PoissonClutter"):
        HypothesisFilter(MOTION, no_clutter, HFISSTWeights(), ExhaustiveGenerator())
    flat_h = SimpleNamespace(measurement=SimpleNamespace(H=np.zeros(4), R=np.eye(1)),
                             detection=DetectionModel(0.8, REGION), clutter=PoissonClutter(1.0, REGION))
    with pytest.raises(ValueError, match=r"^sensor H must be a 2-D array, got shape \(4,\)$"):
        HypothesisFilter(MOTION, flat_h, HFISSTWeights(), ExhaustiveGenerator())
    bad_r = SimpleNamespace(measurement=SimpleNamespace(H=H, R=np.eye(3)), detection=DetectionModel(0.8, REGION),
                            clutter=PoissonClutter(1.0, REGION))
    with pytest.raises(ValueError, match=r"^sensor R must be 2x2, got shape \(3, 3\)$"):
        HypothesisFilter(MOTION, bad_r, HFISSTWeights(), ExhaustiveGenerator())
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), means=X0, covs=P0)
    assert f.max_hypotheses == 100 and f.dt == 1.0 and f.cap == "top"
    f.step(Z)
    assert f.store.labels.dtype == np.int64


def test_more_association_children_than_one_chunk_get_each_twin_once():
    """Five objects, two birth regions and seven returns: over 2^15 association children, so the
    twins are built chunk by chunk; each appears once, for exactly the children that allow it."""
    X = np.array([[0.0, 0.0, 0, 0], [3.0, 1.0, 0, 0], [-4.0, 2.0, 0, 0], [6.0, -3.0, 0, 0], [-2.0, -5.0, 0, 0]])
    P = np.repeat(np.eye(4)[None], 5, axis=0)
    pop = SingleEventPopulation(SingleEventBirthDeath(0.01, 0.02, 2), birth_densities=_births())
    f = HypothesisFilter(MOTION, _sensor(0.8), HFISSTWeights(), ExhaustiveGenerator(), population=pop,
                         means=X, covs=P)
    Z7 = np.array([[0.2, 0.1], [3.1, 1.2], [-4.2, 2.1], [6.1, -2.8], [-2.2, -4.9], [-30.0, 10.0], [30.0, 10.0]])
    ch = f.expand(Z7)
    assoc = ch.kind == ChildSet.ASSOCIATION
    assert assoc.sum() > 1 << 15
    keys = {(int(k), int(a), e.tobytes()) for k, a, e in zip(ch.kind, ch.arg, ch.events)}
    assert len(keys) == len(ch)  # no twin twice
    no_birth = assoc & np.all(ch.events < 5, axis=1)
    assert np.sum(ch.kind == ChildSet.UNDETECTED_BIRTH) == 2 * no_birth.sum()  # one per birth region
    undetected = sum(5 - len(set(e[e >= 0].tolist())) for e in ch.events[no_birth])
    assert np.sum(ch.kind == ChildSet.DEATH) == undetected  # one per object that went undetected
