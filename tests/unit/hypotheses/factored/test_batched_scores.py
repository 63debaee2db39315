"""A scan's scores in the sensor frame without the dense matrices, on real scans of the documented radar (second-order
EKF in ``(ρ, az, el, ρ̇)``):

* the birth likelihoods in one batch (:func:`hypotrack.hypotheses.factored.births.birth_loglik`) against each
  birth term's own (:meth:`GaussianBirthTerm.loglik`): the catalogue's admissible-region terms, a return put on
  a term's gate edge along the direction where the bound is tight, and terms the batch cannot take (the
  population's own call, bit for bit);
* the tracks' gated pairs (:func:`hypotrack.hypotheses.factored.scores.sensor_frame_pairs`) against the engine's
  dense matrices, bit for bit, tracks in and out of view, with and without ``gate_out_of_view``."""

import numpy as np
import pytest
import yaml

from hypotrack.association import gate_threshold
from hypotrack.experiments.ssa_catalogue.run import initial_tracks, make_motion, make_problem, make_tracker, tracker_sensor
from hypotrack.experiments.ssa_catalogue.scale import clone_scenario
from hypotrack.hypotheses import GaussianBirthTerm, LabeledMultiBernoulliPopulation
from hypotrack.hypotheses.factored.births import batchable, birth_loglik
from hypotrack.hypotheses.factored.lane import predict_each
from hypotrack.hypotheses.factored.scores import score_tracks, sensor_frame_pairs
from hypotrack.hypotheses.tracks import TrackStore

N_SCANS = 7


@pytest.fixture(scope="module")
def scans_and_terms():
    """(Z, population, the radar set to the scan's GMST, predicted tracks, engine) at each scan of the default
    section's scale population (the catalogue cloned, N = 10,855) as δ-GLMB steps it: the population holds the
    adaptive birth terms of the previous scan's unexplained returns; the tracks are the lane's in view at the
    scan and 300 others (out of view), predicted to it."""
    with open("workflows/config/default.yaml") as fh:
        cfg = dict(yaml.safe_load(fh)["ssa_catalogue"], n_scans=N_SCANS)
    objects, unknown, sc, init_seed = clone_scenario(cfg, 10855, 1, n_scans=N_SCANS, chunk=20000)
    tsensor = tracker_sensor(sc.sensors[0])
    means, covs, labels = initial_tracks(sc, unknown, cfg, init_seed)
    tr = make_tracker("glmb", cfg, make_problem(cfg, tsensor, make_motion(cfg), means, covs, labels), 1)
    out = []
    for k, (t_k, Z) in enumerate(sc.scan_list(0)):
        tsensor.at(sc.theta[k])
        Zt = tsensor.returns(Z)
        pop = tr.engine.population
        tr.step(Zt, float(t_k))
        lane = tr.state().lane
        pick = np.concatenate([np.flatnonzero(tr.engine.sensor.detection.in_view(lane.view[:, :3])),
                               np.random.default_rng(k).choice(len(lane), 300, replace=False)])
        x, P = predict_each(tr.engine.motion, lane.store.means[pick], lane.store.covs[pick], tr.time - lane.times[pick])
        out.append((Zt, pop, lambda theta=sc.theta[k]: tsensor.at(theta), TrackStore(x, P, lane.store.labels[pick]),
                    tr.engine))
    return out


def _own(term, Z):
    """Per return: the term's squared distance and whether the per-component bound passes it."""
    meas = term.measurement
    z_pred, S, _, _ = (a[0] for a in meas.innovation(term.mean[None], term.cov[None]))
    nu = meas.residual(Z, z_pred[None])[:, 0]
    d2 = np.einsum("mi,ij,mj->m", nu, np.linalg.inv(S), nu)
    gate = gate_threshold(term.gate_probability, len(z_pred))
    return d2, np.all(np.abs(nu) <= np.sqrt(gate * np.diag(S)), axis=1), gate


def test_every_likelihood_is_the_terms_own_and_the_bound_keeps_every_gated_pair(scans_and_terms):
    n_terms = n_gated = n_bound_only = n_pairs = n_bound = 0
    for Z, pop, at, _, _ in scans_and_terms:
        at()
        want = pop.birth_loglik(Z)
        got = birth_loglik(pop, Z)
        assert got.shape == want.shape == (len(Z), pop.n_birth_regions)
        np.testing.assert_array_equal(np.isfinite(got), np.isfinite(want))  # the same gated pairs
        fin = np.isfinite(want)
        # the sensor frame's batched EKF rounds differently from one term at a time (as the fast path's)
        np.testing.assert_allclose(got[fin], want[fin], rtol=1e-12, atol=0)
        for term in pop.birth_densities:
            d2, bound, gate = _own(term, Z)
            assert not np.any((d2 <= gate) & ~bound)  # the bound never rejects a gated pair
            n_gated += int(np.sum(d2 <= gate))
            n_bound += int(bound.sum())
            n_bound_only += int(np.sum(bound & (d2 > gate)))
        n_terms += pop.n_birth_regions
        n_pairs += want.size
    # the scans hold what the check is for: many admissible terms, gated returns, pairs the bound passes that
    # only the full test rejects, and most pairs rejected by the bound alone
    assert n_terms > 50 and n_gated > 0 and n_bound_only > 0 and n_bound < 0.2 * n_pairs


def test_a_return_on_the_gate_edge_where_the_bound_is_tight(scans_and_terms):
    """ν along ``S e_0`` makes the bound on the range an equality: d² = γ(1 − 1e-6) is kept, (1 + 1e-6) is not."""
    Z, pop, at, _, _ = next(s for s in scans_and_terms if s[1].n_birth_regions)
    at()
    term = pop.birth_densities[0]
    meas = term.measurement
    z_pred, S, _, _ = (a[0] for a in meas.innovation(term.mean[None], term.cov[None]))
    gate = gate_threshold(term.gate_probability, 4)
    u = S[:, 0] / np.sqrt(S[0, 0])  # νᵀS⁻¹ν = 1 and ν_0² / S_00 = 1: the bound is an equality
    edge = np.array([z_pred + np.sqrt(gate * f) * u for f in (1 - 1e-6, 1 + 1e-6)])
    one = LabeledMultiBernoulliPopulation(birth_densities=[term], r_birth=0.01)
    want, got = one.birth_loglik(edge), birth_loglik(one, edge)
    assert np.isfinite(want[0, 0]) and not np.isfinite(want[1, 0])
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(want))
    np.testing.assert_allclose(got[0, 0], want[0, 0], rtol=1e-12)


def test_terms_the_batch_cannot_take_go_through_the_population():
    """Linear terms (no measurement model), mixed gates, an empty scan: the population's own numbers."""
    H = np.hstack([np.eye(2), np.zeros((2, 2))])
    R = np.eye(2) * 0.5
    terms = [GaussianBirthTerm(np.array([0.0, 0.0, 1.0, 0.0]), np.eye(4) * 4.0, H, R, 0.99),
             GaussianBirthTerm(np.array([5.0, 1.0, 0.0, 0.0]), np.eye(4) * 2.0, H, R, 0.9)]
    pop = LabeledMultiBernoulliPopulation(birth_densities=terms, r_birth=0.1)
    assert not batchable(pop.birth_densities) and not batchable(())
    Z = np.array([[0.5, -0.3], [5.2, 1.1], [20.0, 20.0]])
    got = birth_loglik(pop, Z)
    np.testing.assert_array_equal(got, pop.birth_loglik(Z))
    # hand-computed: term 0, return 0: S = 4.5 I, d² = (0.25 + 0.09) / 4.5; log N = −d²/2 − log(2π · 4.5)
    np.testing.assert_allclose(got[0, 0], -0.5 * 0.34 / 4.5 - np.log(2 * np.pi * 4.5), rtol=1e-13)
    assert np.isneginf(got[2]).all()
    assert birth_loglik(pop, np.zeros((0, 2))).shape == (0, 2)


@pytest.mark.parametrize("gate_out_of_view", [True, False])
def test_the_sensor_frames_gated_pairs_are_the_dense_matrices_entries(scans_and_terms, gate_out_of_view):
    n_gated = n_out = 0
    for Z, _, at, pred, engine in scans_and_terms:
        at()
        dense = score_tracks(engine, pred, Z, gate_out_of_view=gate_out_of_view, dense_pairs=10**12)
        pairs = sensor_frame_pairs(engine, pred, Z, gate_out_of_view=gate_out_of_view)
        assert dense.loglik is not None and pairs.loglik is None  # the two forms
        every = np.arange(len(Z)), np.arange(len(pred))
        la, aa, pa, _ = dense.block(*every)
        lb, ab, pb, _ = pairs.block(*every)
        np.testing.assert_array_equal(ab, aa)
        np.testing.assert_array_equal(lb[ab], la[aa])  # bit for bit
        np.testing.assert_array_equal(pb, pa)
        n_gated += int(aa.sum())
        n_out += int(np.sum(pa == 0))
    assert n_gated > 500 and n_out > 1000  # returns gated, and tracks out of view scored alike
