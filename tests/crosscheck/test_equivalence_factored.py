"""The factored engine against the unfactored one.

(a) Separable models — the δ-GLMB (GLMB weights, labeled multi-Bernoulli population with a gated
    birth term) and Reid's HOMHT with Poisson births seeded at returns — with exhaustive
    generation and no binding cap: after every scan the product of the groups, expanded into
    joint hypotheses, is the unfactored filter's posterior, weight for weight (1e-9) and track
    for track (means and covariances, 1e-9). The scene has clutter, a detected birth, deaths
    (GLMB), a merge through an object just out of view whose gate holds its neighbour's return
    (it cannot take it: the joint factorises and is split exactly a scan later), and a genuine
    merge of two objects that share a return (whose joint then never factorises: checked).
(b) Seed 000's single-event population couples all objects; the factored engine applies it per
    group. The difference in the cardinality distribution is computed by hand on a scan
    without returns and measured on the scene of (a).
(c) The marginal-product split (Beard, Vo & Vo 2020) of two objects that shared a return and then
    moved apart: the split's marginals, KL and L1 equal a brute-force computation from the
    unfactored filter's joint. (Objects that *crossed* never split: some hypothesis has each
    label's track following the other object, so their gates keep overlapping.)
"""

import itertools

import numpy as np
import pytest

from hypotrack.hypotheses import (
    ExhaustiveGenerator,
    FactoredFilter,
    FISSTPoissonWeights,
    GaussianBirthTerm,
    GLMBWeights,
    HypothesisFilter,
    LabeledMultiBernoulliPopulation,
    SingleEventPopulation,
    cardinality_total_variation,
    homht,
)
from hypotrack.hypotheses.factored_groups import factorise
from hypotrack.models.motion import ConstantVelocity
from hypotrack.models.population import SingleEventBirthDeath, UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor

R = np.eye(2) * 0.3
MOTION = ConstantVelocity(q=0.02)
VIEW = Box([-10.0, -10.0], [10.0, 10.0])
P_D = 0.85
SENSOR = position_sensor(R, P_D, VIEW, 1.0, Box([-20.0, -20.0], [20.0, 20.0]))
H = SENSOR.measurement.H
GATE = 0.99
# a, b share a return at scan 2 (genuine merge); c starts out of view beside d, its gate holds d's
# return at scan 1 (merge), then it moves away (exact split at scan 2)
X0 = np.array([[-3.0, 0.0, 1.0, 0.0], [3.0, 0.0, -1.0, 0.0], [10.3, -5.0, 1.0, 0.0], [9.0, -5.0, 0.0, 0.0]])
P0 = np.repeat(np.diag([0.5, 0.5, 0.05, 0.05])[None], 4, axis=0)
BIRTH = GaussianBirthTerm(np.array([-6.0, 6.0, 0.0, 0.0]), np.diag([1.0, 1.0, 0.2, 0.2]), H, R, gate_probability=GATE)
SCANS = [np.array([[-2.1, 0.1], [9.1, -5.2], [-8.0, -8.0]]),  # a, d (also in c's gate), clutter
         np.array([[0.0, 0.2], [8.9, -4.9], [-5.8, 6.3]]),  # between a and b, d, a birth
         np.array([[0.9, -0.1], [9.0, -5.1], [4.0, -8.5]])]  # a or b, d, clutter
BIRTH_REGION = UniformBirthDensity(VIEW, np.eye(2) * 0.05)


def glmb_exhaustive():
    """The glmb preset's weights and population with exhaustive generation (no sampling)."""
    pop = LabeledMultiBernoulliPopulation([BIRTH], r_birth=0.1, p_survive=0.95)
    return HypothesisFilter(MOTION, SENSOR, GLMBWeights(), ExhaustiveGenerator(), merge_duplicates=True, population=pop,
                            max_hypotheses=10**6, gate_probability=GATE, means=X0, covs=P0, seed=0)


def homht_poisson_births():
    return homht(MOTION, SENSOR, merge_duplicates=True, birth_intensity=2e-3, birth_density=BIRTH_REGION, max_hypotheses=10**6,
                 gate_probability=GATE, means=X0, covs=P0, seed=0)


def _track_keys(store):
    rows = np.round(np.hstack([store.means, store.covs.reshape(len(store), -1)]), 6)
    return [tuple(r) for r in rows]


def _key(means, covs):
    return tuple(sorted(tuple(np.round(np.concatenate([m, c.ravel()]), 6)) for m, c in zip(means, covs)))


def _table(items):
    """{key: (weight, means, covs in key order)} from (weight, [(track key, mean, cov), ...])."""
    out = {}
    for w, tracks in items:
        tracks = sorted(tracks, key=lambda x: x[0])
        k = tuple(x[0] for x in tracks)
        assert k not in out, "two hypotheses with the same tracks (duplicates are merged)"
        out[k] = (w, np.array([x[1] for x in tracks]), np.array([x[2] for x in tracks]))
    return out


def unfactored_table(f):
    st, tk = f.store, _track_keys(f.store)
    return _table((np.exp(lw), [(tk[j], st.means[j], st.covs[j]) for j in t])
                  for lw, t in zip(f.log_weights, f.track_lists))


def factored_table(ff):
    """The product of the groups expanded here (itertools), not by the engine's product()."""
    per_group = []
    for g in ff.groups:
        tk = _track_keys(g.store)
        per_group.append([(lw, [(tk[j], g.store.means[j], g.store.covs[j]) for j in t])
                          for lw, t in zip(g.log_w, g.tracks)])
    return _table((np.exp(sum(h[0] for h in combo)), [x for h in combo for x in h[1]])
                  for combo in itertools.product(*per_group))


def unfactored_after_each_scan(runs, make):
    """The unfactored filter's (table, posterior) after each scan of SCANS, computed once per model.

    The run is deterministic (seed 0) and the same in every test of (a), so they share it through
    the module-scoped ``unfactored_runs`` (a fixture, not a module global: it is rebuilt in every
    pytest session, as mutation testing needs).
    """
    if make not in runs:
        u, runs[make] = make(), []
        for Z in SCANS:
            u.step(Z)
            runs[make].append((unfactored_table(u), u.posterior()))
    return runs[make]


@pytest.fixture(scope="module")
def unfactored_runs():
    return {}


def _stacked(table, keys):
    """Weights, and means and covariances flattened, of the hypotheses ``keys`` in that order."""
    return (np.array([table[k][0] for k in keys]),
            np.concatenate([table[k][1].ravel() for k in keys]),
            np.concatenate([table[k][2].ravel() for k in keys]))


def assert_same_posterior(unfactored, ff):
    """``unfactored`` is one entry of :func:`unfactored_after_each_scan`: (table, posterior)."""
    (U, pu), J = unfactored, factored_table(ff)
    assert U.keys() == J.keys()
    # Hypothesis by hypothesis (the same key order on both sides), every weight, mean and
    # covariance entry within 1e-9, compared in one array each.
    keys = list(U)
    for got, want in zip(_stacked(J, keys), _stacked(U, keys)):
        assert got.shape == want.shape
        np.testing.assert_allclose(got, want, atol=1e-9, rtol=0)
    pf = ff.posterior()
    n = max(len(pu.cardinality), len(pf.cardinality))
    np.testing.assert_allclose(np.pad(pf.cardinality, (0, n - len(pf.cardinality))),
                               np.pad(pu.cardinality, (0, n - len(pu.cardinality))), atol=1e-9)
    assert pf.expected_number == pytest.approx(pu.expected_number, abs=1e-9)
    assert pf.map_estimate.weight == pytest.approx(pu.map_estimate.weight, abs=1e-9)
    assert _key(pf.map_estimate.means, pf.map_estimate.covs) == _key(pu.map_estimate.means, pu.map_estimate.covs)
    return len(U)


@pytest.mark.parametrize("make", [glmb_exhaustive, homht_poisson_births], ids=["glmb", "homht"])
def test_a_separable_models_factored_posterior_equals_unfactored(make, unfactored_runs):
    ff = FactoredFilter.from_filter(make(), split="exact")
    assert [len(g.labels) for g in ff.groups] == [1, 1, 1, 1]
    sizes = []
    for Z, unfactored in zip(SCANS, unfactored_after_each_scan(unfactored_runs, make), strict=True):
        ff.step(Z)
        sizes.append(assert_same_posterior(unfactored, ff))
    hist = ff.stats_history
    assert [s["n_merges"] for s in hist] == [1, 1, 0]  # c + d at scan 1, a + b at scan 2
    assert [s["n_exact_splits"] for s in hist] == [0, 1, 0]  # c | d at scan 2
    assert ff.split_records[0].exact and ff.split_records[0].kl < 1e-12 and ff.split_records[0].l1 < 1e-12
    assert sizes[-1] > 5000  # thousands of joint hypotheses, from a few groups
    assert ff.n_joint_hypotheses == sizes[-1] and max(len(g.log_w) for g in ff.groups) < 100
    assert hist[-1]["largest_group"] >= 2
    # births happened and (GLMB) deaths: some hypotheses hold a newborn, some fewer objects
    labels = set(np.concatenate([g.labels for g in ff.groups]).tolist())
    assert max(labels) >= 4
    # the a + b group shares a return: its joint does not factorise (the missing mass is the
    # configuration where both took it), so no split can be exact after a real interaction
    (ab,) = [g for g in ff.groups if {0, 1} <= set(g.labels.tolist())]
    parts = np.where(ab.store.labels == 0, 0, 1)
    record, _ = factorise(ab, parts)
    assert not record.exact and record.l1 > 1e-3


def test_a_glmb_deaths_show_in_the_cardinality():
    ff = FactoredFilter.from_filter(glmb_exhaustive(), split="exact")
    for Z in SCANS[:2]:
        ff.step(Z)
    card = ff.posterior().cardinality
    assert card[:4].sum() > 1e-3  # fewer than the 4 initial objects: deaths
    assert card[5:].sum() > 1e-3  # more: the birth


# ---------------------------------------------------------------- (b) single-event coupling
def _single_event(alpha=0.0, beta=0.05, births="free"):
    model = SingleEventBirthDeath(alpha, beta, 1)
    pop = SingleEventPopulation(model, birth_densities=(BIRTH_REGION,))
    return lambda means, covs: HypothesisFilter(MOTION, SENSOR, FISSTPoissonWeights(), ExhaustiveGenerator(), merge_duplicates=True,
                                                population=pop, max_hypotheses=10**6, gate_probability=GATE,
                                                means=means, covs=covs, seed=0)


def test_b_single_event_per_group_by_hand():
    """Two objects far apart, in view, a scan without returns, deaths only (β, α = 0).

    Unfactored (one event for the scene): no event 1 − 2β with both missed, or one of the two
    dies: P(2) = (1 − 2β)(1 − p_D) / ((1 − 2β)(1 − p_D) + 2β), P(1) the rest, P(0) = 0.
    Factored (one event per group): each object independently alive with
    q = (1 − β)(1 − p_D) / ((1 − β)(1 − p_D) + β): P = (q², 2q(1 − q), (1 − q)²) reversed.
    """
    beta = 0.05
    make = _single_event(beta=beta)
    X = X0[[0, 3]]
    u = make(X, P0[:2])
    ff = FactoredFilter.from_filter(make(X, P0[:2]), births="free")
    u.step(np.zeros((0, 2)))
    ff.step(np.zeros((0, 2)))
    miss = 1 - P_D
    p2 = (1 - 2 * beta) * miss / ((1 - 2 * beta) * miss + 2 * beta)
    q = (1 - beta) * miss / ((1 - beta) * miss + beta)
    np.testing.assert_allclose(u.posterior().cardinality, [0.0, 1 - p2, p2], atol=1e-12)
    np.testing.assert_allclose(ff.posterior().cardinality, [(1 - q) ** 2, 2 * q * (1 - q), q * q], atol=1e-12)
    tv = cardinality_total_variation(u.posterior().cardinality, ff.posterior().cardinality)
    want = 0.5 * ((1 - q) ** 2 + abs(1 - p2 - 2 * q * (1 - q)) + abs(p2 - q * q))
    assert tv == pytest.approx(want, abs=1e-12)
    assert tv == pytest.approx(0.0675, abs=1e-4)  # ~7 % of the cardinality mass moves


def _scene_tv(alpha, beta):
    make = _single_event(alpha=alpha, beta=beta)
    u = make(X0, P0)
    ff = FactoredFilter.from_filter(make(X0, P0), births="free", split="exact")
    tv = []
    for Z in SCANS:
        u.step(Z)
        ff.step(Z)
        tv.append(cardinality_total_variation(u.posterior().cardinality, ff.posterior().cardinality))
    return tv, u.posterior().expected_number, ff.posterior().expected_number


def test_b_single_event_coupling_measured_on_the_scene():
    """The scene of (a) under FISST weights with Poisson clutter (separable, so the difference is
    the population model's alone) and the single-event population: α = 0.01 (one region, the
    view), β = 0.02, births offered to returns in no gate. Measured (deterministic, pinned):
    the total variation between the factored and unfactored cardinality distributions after
    each scan is 0.0066, 0.0215, 0.0245, and the expected number of objects 3.201 (factored)
    against 3.234 (unfactored) after scan 3. Control: with α = β = 0 the model has no events
    and the two coincide."""
    tv, n_u, n_f = _scene_tv(0.01, 0.02)
    np.testing.assert_allclose(tv, [0.006589923317912622, 0.021499001228267037, 0.024522144415719392], rtol=1e-6)
    assert n_u == pytest.approx(3.233660095119319, rel=1e-9) and n_f == pytest.approx(3.2012745583953883, rel=1e-9)
    tv0, n_u0, n_f0 = _scene_tv(0.0, 0.0)
    assert max(tv0) < 1e-12 and n_f0 == pytest.approx(n_u0, abs=1e-12)


# ---------------------------------------------------------------- (c) marginal split
# two objects moving apart vertically; at scan 1 one return lies between them (in both gates)
APART_X0 = np.array([[0.0, 1.0, 0.0, 1.5], [0.0, -1.0, 0.0, -1.5]])
APART_SCANS = [np.array([[0.0, 0.1], [0.1, 2.4]]), np.array([[0.0, 4.1], [0.1, -3.9]])]


def _apart(split):
    f = homht(MOTION, SENSOR, merge_duplicates=True, max_hypotheses=10**6, gate_probability=GATE, means=APART_X0, covs=P0[:2], seed=0)
    return f if split is None else FactoredFilter.from_filter(f, split=split)


def test_c_marginal_split_equals_brute_force_marginals_and_loss():
    u, ff = _apart(None), _apart("marginal")
    for Z in APART_SCANS:
        u.step(Z)
        ff.step(Z)
    assert [s["n_merges"] for s in ff.stats_history] == [1, 0]
    assert [s["n_splits"] for s in ff.stats_history] == [0, 1] and not ff.split_records[-1].exact
    # brute force from the unfactored joint: per-label marginals of the tracks, their product
    joint = [(np.exp(lw), t) for lw, t in zip(u.log_weights, u.track_lists)]
    marg = [{}, {}]
    for w, t in joint:
        for j in t:
            lab = int(u.store.labels[j])
            key = tuple(np.round(u.store.means[j], 9))
            marg[lab][key] = marg[lab].get(key, 0.0) + w
    P = {}
    for w, t in joint:
        P[tuple(tuple(np.round(u.store.means[j], 9)) for j in sorted(t, key=lambda j: u.store.labels[j]))] = w
    Q = {(a, b): wa * wb for a, wa in marg[0].items() for b, wb in marg[1].items()}
    kl = sum(p * np.log(p / Q[k]) for k, p in P.items())
    l1 = sum(abs(P.get(k, 0.0) - q) for k, q in Q.items())
    rec = ff.split_records[-1]
    assert rec.kl == pytest.approx(kl, rel=1e-9) and rec.l1 == pytest.approx(l1, rel=1e-9)
    assert rec.kl > 1e-4 and len(Q) > len(P)  # the product puts mass on pairs the joint lacks
    # the split groups are the marginals
    for g in ff.groups:
        (lab,) = g.labels
        got = {tuple(np.round(g.store.means[t[0]], 9)): np.exp(lw) for lw, t in zip(g.log_w, g.tracks)}
        assert got.keys() == marg[lab].keys()
        for key, w in got.items():
            assert w == pytest.approx(marg[lab][key], abs=1e-12)


@pytest.mark.parametrize("make", [glmb_exhaustive, homht_poisson_births], ids=["glmb", "homht"])
def test_a_out_of_view_tracks_gating_nothing_changes_no_weight(make, unfactored_runs):
    """With ``gate_out_of_view=False`` c (out of view, p_D = 0) does not merge with d at scan 1:
    one merge fewer, no split needed, the same posterior as the unfactored filter at every scan."""
    ff = FactoredFilter.from_filter(make(), split="exact", gate_out_of_view=False)
    for Z, unfactored in zip(SCANS, unfactored_after_each_scan(unfactored_runs, make), strict=True):
        ff.step(Z)
        assert_same_posterior(unfactored, ff)
    assert [s["n_merges"] for s in ff.stats_history] == [0, 1, 0]  # only a + b, at scan 2
    assert [s["n_splits"] for s in ff.stats_history] == [0, 0, 0]
