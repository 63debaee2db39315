"""The ssa_breakup scorecard (:mod:`hypotrack.experiments.ssa_breakup.scorecard`) by hand, on a small scene with a
constant-velocity stand-in for the orbit model (``x' = x + v dt``, ``Φ = [[I, dt I], [0, I]]``,
``Q(dt) = dt / 390 · I``, so that a 390 s gap adds exactly 1 km² to every variance) and a stand-in radar that sees
the positions with ``z > 0`` (a rotation about z, as TEME to Earth-fixed, keeps z)."""

import warnings
from datetime import datetime, timezone
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from scipy.stats import chi2

from hypotrack.experiments.ssa_breakup.scorecard import (completeness, identity_row, next_pass, predict,
                                                         reacquisitions, scorecard_row)
from hypotrack.scenarios.tables import truth_table


class CV:
    """Constant velocity in 3-D with ``Q(dt) = dt / 390 · I``; ``Q`` of a negative interval is not a covariance."""

    @staticmethod
    def _phi(dt):
        phi = np.tile(np.eye(6), (len(dt), 1, 1))
        phi[:, :3, 3:] = dt[:, None, None] * np.eye(3)
        return phi

    def transition(self, X, dt):
        return self.transition_each(X, np.full(len(X), float(dt)))

    def transition_each(self, X, dt):
        phi = self._phi(np.asarray(dt, float))
        return np.einsum("nij,nj->ni", phi, X), phi

    def propagate_each(self, X, dt):
        return self.transition_each(X, dt)[0]

    def Q(self, dt):
        assert dt >= 0, "Q of a negative interval"
        return dt / 390.0 * np.eye(6)

    def Q_each(self, dt):
        assert np.all(np.asarray(dt) >= 0), "Q of a negative interval"
        return np.asarray(dt, float)[:, None, None] / 390.0 * np.eye(6)


P_POS = np.diag([1.0, 1, 1, 0, 0, 0])  # position variance 1, velocity known


def test_predict_by_hand_and_a_zero_interval_copies():
    """dt = -390 s (backwards): x' = x - 390 v; P' = Φ P Φᵀ + Q(|dt|): with velocity variance 1e-4, the position
    variance 1 + 390² · 1e-4 + 1 = 17.21, the position-velocity covariance -390 · 1e-4 = -0.039, the velocity's
    1e-4 + 1."""
    x = np.array([1.0, 2.0, 3.0, 0.5, -1.0, 0.0])
    P = np.diag([1.0, 1, 1, 1e-4, 1e-4, 1e-4])
    xp, Pp = predict(CV(), x, P, -390.0)
    np.testing.assert_allclose(xp, [1 - 195.0, 2 + 390.0, 3.0, 0.5, -1.0, 0.0])
    want = np.zeros((6, 6))
    want[:3, :3] = 17.21 * np.eye(3)
    want[:3, 3:] = want[3:, :3] = -0.039 * np.eye(3)
    want[3:, 3:] = 1.0001 * np.eye(3)
    np.testing.assert_allclose(Pp, want, rtol=1e-12, atol=1e-12)
    x1, P1 = predict(CV(), x, P, 1.0)  # one second: x + v, P + Φ-terms + I/390
    np.testing.assert_allclose(x1, [1.5, 1.0, 3.0, 0.5, -1.0, 0.0])
    assert P1[0, 0] == pytest.approx(1 + 1e-4 + 1 / 390) and P1[0, 3] == pytest.approx(1e-4)
    x0, P0 = predict(CV(), x, P, 0)
    assert x0 is not x and P0 is not P and np.array_equal(x0, x) and np.array_equal(P0, P)
    x0[0], P0[0, 0] = 99.0, 99.0  # the copies are the caller's own
    assert x[0] == 1.0 and P[0, 0] == 1.0


def _scene():
    """Objects 1-3 in view at scans 0-3 (0, 10, 400, 410 s: two passes, the gap 390 s); object 4 alone at scans 4
    and 5 (1000 and 2000 s: two passes). At scan 2: 1 at (64, 0, 0), 2 at (64, 3, 0), 3 at (64, 0, 100), 5 at
    (-60, 0, 0), all moving (0, 7, 0); at scan 5: 4 at (50, 0, 0) moving (0, 1, 0)."""
    rows = []
    for s, t in enumerate((0.0, 10.0, 400.0, 410.0)):
        for k, pos in ((3, (64, 0, 100)), (1, (64, 0, 0)), (2, (64, 3, 0))):  # the nearest neighbour not listed first
            rows.append((s, t, k, [*pos, 0, 7, 0]))
    rows.append((2, 400.0, 5, [-60, 0, 0, 0, 7, 0]))  # object 5, seen once: 124 km from 1 (its sum with 1: 4 km)
    rows += [(4, 1000.0, 4, [50, 0, 0, 0, 1, 0]), (5, 2000.0, 4, [50, 0, 0, 0, 1, 0])]
    s, t, k, x = zip(*rows)
    return truth_table(s, t, k, np.array(x, float), [True] * len(rows))


def _ends():
    """Track ends: 1 predicted 390 s to (64.75, 1, 0) (error (0.75, 1, 0), 1.25 km; its velocity variance 1/390²
    adds 390² / 390² = 1 to the position's, and Q another 1: 3); 2 predicted 395 s (its state
    at 5 s, its pass ending at 10 s) to (74, 3, 0) (error 10 km); 4 predicted 390 s from 1610 s (its pass ends at
    1000 s) to (50, 0, 0.5); 3's pass 1 has no next pass and a final end (pass -1) is no re-acquisition."""
    P1 = np.diag([1.0, 1, 1] + [390.0**-2] * 3)
    return [dict(target=1, pass_no=0, time=10.0, t_x=10.0, x=np.array([64.75, 1 - 7 * 390.0, 0, 0, 7, 0]), P=P1),
            dict(target=3, pass_no=1, time=410.0, t_x=410.0, x=np.zeros(6), P=P_POS),
            dict(target=2, pass_no=0, time=10.0, t_x=5.0, x=np.array([74.0, 3 - 7 * 395.0, 0, 0, 7, 0]), P=P_POS),
            dict(target=1, pass_no=-1, time=410.0, t_x=410.0, x=np.zeros(6), P=P_POS),
            dict(target=4, pass_no=0, time=1000.0, t_x=1610.0, x=np.array([50.0, 0, 0.5, 0, 0, 0]), P=P_POS)]


# object 2's error (10, 0, 0) in the RIC frame of r = (64, 3, 0), v = (0, 7, 0): R = r/|r|, C = z, I = C x R
ERR2 = (640 / np.sqrt(4105), -30 / np.sqrt(4105), 0.0)
D2 = (1.5625 / 3, 100 / (1 + 395 / 390), 0.25 / 2)  # |e|² over the predicted position variance


def test_reacquisitions_by_hand():
    """P' position block: 3 for object 1, 1 + dt/390 for the others (2 for 390 s). Object 1's nearest other object
    in view is 2, 3 km away; from the prediction (-0.75, 2, 0): d² = 4.5625 / (3 + σ²) = 0.380 for σ = 3 km,
    inside χ²₃(0.07) = 0.449 (it would not be with 2σ instead of σ², without the track's own variance, 0.507,
    or measured from the truth, 9 / 12). Object 2's nearest is 1, 10.4 km from its prediction: outside. Object 4
    is alone: no neighbour in the gate."""
    r = reacquisitions(SimpleNamespace(ends=_ends()), _scene(), CV(), 3.0, 0.07, 1.25)
    assert list(r.columns) == ["target", "pass_no", "t_end", "gap_s", "err_r", "err_i", "err_c", "d2", "within",
                               "nn_in_gate"]
    assert r["target"].tolist() == [1, 2, 4] and r["pass_no"].tolist() == [0, 0, 0]
    assert r["t_end"].tolist() == [10.0, 10.0, 1000.0] and r["gap_s"].tolist() == [390.0, 390.0, 1000.0]
    np.testing.assert_allclose(r[["err_r", "err_i", "err_c"]].to_numpy(), [(0.75, 1.0, 0.0), ERR2, (0.0, 0.0, 0.5)],
                               atol=1e-12)
    np.testing.assert_allclose(r["d2"], D2, rtol=1e-12)
    assert r["within"].tolist() == [True, False, True]  # 1.25 km is within 1.25 km
    assert r["nn_in_gate"].tolist() == [True, False, False]
    assert 4.5625 / 12 < chi2.ppf(0.07, 3) < min(4.5625 / 9, 9 / 12)
    # the gate at 0.05 (χ²₃ = 0.352) leaves object 1's neighbour out
    assert reacquisitions(SimpleNamespace(ends=_ends()), _scene(), CV(), 3.0, 0.05, 1.25)["nn_in_gate"].sum() == 0
    none = reacquisitions(SimpleNamespace(ends=_ends()[1:2]), _scene(), CV(), 3.0, 0.07, 1.25)
    assert none.empty and list(none.columns) == list(r.columns)


class Radar:
    @staticmethod
    def in_view(r_ef):
        return r_ef[..., 2] > 0


class Scene:
    """Catalogue 1-4 after the scans (last at 2000 s), static: 1 in view (z = 5) from 2090 s; 2 never (z = -5);
    3 in view from 2030 s but its states invalid (decayed); 4 in view from 2060 s."""

    start = datetime(2024, 3, 1, tzinfo=timezone.utc)
    times = np.array([0.0, 10.0, 400.0, 410.0, 1000.0, 2000.0])
    sensors = [Radar()]
    catalogue = pd.DataFrame(dict(norad=[1, 2, 3, 4]))
    truth = _scene()
    POS = np.array([[64.0, 0, 5], [10, 10, -5], [1, 1, 1], [7, 7, 7]])
    FROM = np.array([2090.0, np.inf, 2030.0, 2060.0])

    def states(self, grid):
        X = np.zeros((4, len(grid), 6))
        X[..., :3] = self.POS[:, None]
        X[..., 2] = np.where(grid[None] >= self.FROM[:, None], np.abs(X[..., 2]), -np.abs(X[..., 2]))
        valid = np.ones((4, len(grid)), bool)
        valid[2] = False
        return X, valid


def test_next_pass_by_hand():
    """After 2000 s on a 30 s grid to 300 s: 1 at 2090 s, 2 never (the horizon's end, 2300 s, included), 3 never
    valid (its first valid instant in view: none, so the end), 4 at 2060 s; on a 60 s grid 1 at 2120 s."""
    t, X, ok = next_pass(Scene(), 2000.0, 300.0)
    assert t.tolist() == [2090.0, 2300.0, 2300.0, 2060.0] and ok.tolist() == [True, True, False, True]
    np.testing.assert_array_equal(X[:, :3], [[64, 0, 5], [10, 10, -5], [1, 1, 1], [7, 7, 7]])
    t, _, _ = next_pass(Scene(), 2000.0, 300.0, step_s=60.0)
    assert t.tolist() == [2120.0, 2300.0, 2300.0, 2060.0]
    t, _, _ = next_pass(Scene(), 2000.0, 299.5)  # the grid ends at 270 s
    assert t.tolist() == [2090.0, 2270.0, 2270.0, 2060.0]


class EastRadar:
    """Sees the Earth-fixed x > 0 (by x / |r|, which is 0/0 for a decayed object's zero state)."""

    @staticmethod
    def in_view(r_ef):
        return r_ef[..., 0] / np.linalg.norm(r_ef, axis=-1) > 0


class TurningScene(Scene):
    """Two objects fixed in the Earth frame at (100, ±7000, 0) km, just east of the radar's boundary x = 0, given
    in TEME (rotated back by GMST at each instant, from the frames module: the reference), and a decayed one (zero
    state, invalid). Any other Earth angle than the GMST turns one of the two out of view."""

    sensors = [EastRadar()]
    catalogue = pd.DataFrame(dict(norad=[1, 2, 3]))

    def states(self, grid):
        from hypotrack.scenarios.catalogue.frames import gmst
        from hypotrack.scenarios.catalogue.propagation import time_grid_jd

        th = gmst(*time_grid_jd(self.start, grid))
        c, s = np.cos(th), np.sin(th)
        X = np.zeros((3, len(grid), 6))
        for i, y in enumerate((7000.0, -7000.0)):
            X[i, :, 0], X[i, :, 1] = c * 100.0 - s * y, s * 100.0 + c * y
        valid = np.ones((3, len(grid)), bool)
        valid[2] = False
        return X, valid


def test_next_pass_sees_the_earth_fixed_frame_at_the_right_angle_quietly():
    for start in (datetime(2024, 3, 1, tzinfo=timezone.utc), datetime(2024, 3, 1, 13, 20, tzinfo=timezone.utc)):
        sc = TurningScene()
        sc.start = start
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            t, _, ok = next_pass(sc, 100.0, 300.0)
        assert t.tolist() == [130.0, 130.0, 400.0] and ok.tolist() == [True, True, False], start


def _final():
    """Final tracks: 1 at (64, 0, 5.75) at 1990 s moving 0.01 km/s in y: at 2090 s (0, 1, 0.75) off, 1.25 km;
    2 exactly at its state; 3 (invalid) anywhere; 4 without a track."""
    return [dict(target=1, pass_no=-1, time=2000.0, t_x=1990.0, x=np.array([64.0, 0, 5.75, 0, 0.01, 0]), P=P_POS),
            dict(target=1, pass_no=0, time=10.0, t_x=10.0, x=np.array([64.0, 0, 5, 0, 0, 0]), P=P_POS),
            dict(target=2, pass_no=-1, time=2000.0, t_x=2000.0, x=np.array([10.0, 10, -5, 0, 0, 0]), P=P_POS),
            dict(target=3, pass_no=-1, time=2000.0, t_x=2000.0, x=np.array([1.0, 1, -1, 0, 0, 0]), P=P_POS)]


def test_completeness_by_hand():
    """Valid next passes: 1, 2, 4 (3 is invalid): 1 (1.25 km off) and 2 complete within 1.25 km, 4 has no track."""
    assert completeness(SimpleNamespace(ends=_final()), Scene(), CV(), 300.0, 1.25) == (2, 3)
    assert completeness(SimpleNamespace(ends=_final()), Scene(), CV(), 300.0, 1.2) == (1, 3)
    # no held track: none complete, all three counted
    assert completeness(SimpleNamespace(ends=_final()[1:2]), Scene(), CV(), 300.0, 1.25) == (0, 3)


def _run():
    """Returns (scan, origin, label): 16 of objects, one of clutter. Owners (from the assignment): 1->1, 2->2,
    3->3, 4->4, 5->4. Object 1's return at scan 2 to label 2 is a cross-tag (label 2 on no object then:
    'elsewhere'); object 2's at scan 0 and 2 and 3's at scan 3 are uncorrelated; object 4's to label 9 (no owner)
    at scans 4 and 5 are orphans: 10 correct, 1 cross-tag, 2 orphans, 3 uncorrelated."""
    returns = pd.DataFrame([(0, 1, 1), (1, 1, 1), (2, 1, 2), (3, 1, 1), (0, 2, -1), (1, 2, 2), (2, 2, -1), (3, 2, 2),
                            (0, 3, 3), (1, 3, 3), (2, 3, 3), (3, 3, -1), (4, 4, 9), (4, 4, 4), (5, 4, 5), (5, 4, 9),
                            (1, -1, 7)], columns=["scan", "origin", "label"])
    assign = pd.DataFrame([(s, 1, 1) for s in range(4)] + [(0, 2, 2), (1, 2, 2), (2, 2, -1), (3, 2, 2)]
                          + [(s, 3, 3) for s in range(4)] + [(4, 4, 4), (5, 4, 5)], columns=["scan", "target", "label"])
    per_scan = pd.DataFrame(dict(scan=range(6), n_estimates=[3, 3, 2, 3, 1, 1], false=[0, 1, 0, 0, 0, 1],
                                 duplicate=[1, 0, 0, 0, 0, 0], n_in_view=[3, 3, 3, 3, 1, 1],
                                 unphysical_map=[0, 0, 1, 0, 0, 0], unphysical_hypotheses=[0, 2, 4, 0, 0, 0],
                                 cpu_s=[0.5] * 6, gospa_loc=[1.0, 1, 1, 1, 0, 0], gospa_missed=[0.0, 0, 5, 0, 0, 0],
                                 gospa_false=[0.0, 5, 0, 0, 0, 5]))
    return SimpleNamespace(tracker="glmb", returns=returns, assign=assign, per_scan=per_scan,
                           ends=_ends() + _final()[::2])


def test_identity_row_by_hand():
    """16 object returns, 1 cross-tag (625 per 10⁴), 3 uncorrelated (1875); one identity switch (object 4: label 4
    then 5) over 14 object-scans in view (714.29 per 10⁴)."""
    assert identity_row(_run()) == dict(tracker="glmb", object_returns=16, cross_tags=1, cross_tags_per_1e4=625.0,
                                        catalogue_cross_tags_per_1e4=625.0, id_switches=1,
                                        id_switches_per_1e4=pytest.approx(1e4 / 14), uncorrelated_per_1e4=1875.0)


def test_catalogue_cross_tags_charge_a_catalogued_label_carried_by_another_object():
    """Objects 1-5 catalogued under their own numbers: label 5, which object 4 carried at scan 5 (its purity owner),
    is object 5's entry, so object 4's return to it is a second cross-tag (1250 per 10⁴); with only 1-4
    catalogued, label 5 is a newborn's and keeps its purity owner (625)."""
    assert identity_row(_run(), (1, 2, 3, 4, 5))["catalogue_cross_tags_per_1e4"] == 1250.0
    assert identity_row(_run(), (1, 2, 3, 4))["catalogue_cross_tags_per_1e4"] == 625.0


def test_scorecard_row_by_hand():
    """Every column of the scene above (catalogue 1-4, object 3 unknown: catalogued 1, 2, 4)."""
    cfg = dict(metrics=dict(completeness_km=1.25, next_pass_horizon_s=300.0), radar=dict(sigma_km=3.0),
               model=dict(gate_probability=0.07))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        row = scorecard_row(_run(), (None, [3], Scene(), None), cfg, CV())
    want = dict(
        tracker="glmb", n_objects=4, n_scans=6, object_returns=16, correct_per_1e4=6250.0, cross_tags_per_1e4=625.0,
        orphan_per_1e4=1250.0, uncorrelated_per_1e4=1875.0, cross_tags=1,
        catalogue_cross_tags_per_1e4=625.0, catalogue_cross_tags=1,  # labels 1, 2, 4 on their own objects
        completeness=2 / 3,
        false_per_1000=2e3 / 13, duplicate_per_1000=1e3 / 13, reacquisitions=3, reacq_within_km=2 / 3,
        rms_radial_km=np.sqrt((0.75**2 + ERR2[0] ** 2) / 3), rms_intrack_km=np.sqrt((1 + ERR2[1] ** 2) / 3),
        rms_crosstrack_km=np.sqrt(0.25 / 3),
        realism_95=2 / 3,  # d² 0.52 and 0.125 inside χ²₃(0.95) = 7.81, 49.7 outside
        realism_mean_d2=sum(D2) / 9, nn_in_gate_share=1 / 3,
        # first detections at 0 s (object 1) and 1000 s (object 4); their passes ending 10 s and 1000 s re-acquire
        time_to_orbit_s=5.0, objects_with_orbit=2,
        unphysical_map_per_scan=1 / 6, unphysical_hypotheses_per_scan=1.0, unphysical_hypotheses_max=4.0, cpu_s=3.0,
        xtag_newborn_per_1e4=0.0, xtag_own_label_per_1e4=0.0, xtag_carried_label_per_1e4=0.0,
        xtag_elsewhere_per_1e4=625.0, id_switches=1, id_switches_per_1e4=1e4 / 14,
        # first returns: 1 to 1, 2 (scan 1) to 2, 4 (scan 4, first in table order) to 9: 2 of 3
        first_return_own=2 / 3,
        # passes 0 -> 1: 1 keeps 1, 2 keeps 2 (its scan 2 unassigned), 3 keeps 3, 4 goes from 4 to 5: 3 of 4
        reacquired_same_label=0.75,
        gospa_localisation_per_object_km=4 / 14, gospa_missed_per_object_km=5 / 14, gospa_false_per_object_km=10 / 14,
        gospa_per_object_km=19 / 14)
    assert list(row) == list(want)
    for k, v in want.items():
        assert row[k] == (v if isinstance(v, str) else pytest.approx(v, rel=1e-12, abs=1e-12)), k
    assert isinstance(row["reacquisitions"], int) and isinstance(row["cross_tags"], int)


class DecayedScene(Scene):
    def states(self, grid):
        X, valid = super().states(grid)
        return X, np.zeros_like(valid)


def test_scorecard_row_with_nothing_to_reacquire_is_nan_quietly():
    """No held track and every catalogued object decayed: no re-acquisition, no completeness, no time to orbit —
    NaN (and 0 objects with an orbit), without a warning (no mean of an empty array)."""
    run = _run()
    run.ends = []
    cfg = dict(metrics=dict(completeness_km=1.25, next_pass_horizon_s=300.0), radar=dict(sigma_km=3.0),
               model=dict(gate_probability=0.07))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        row = scorecard_row(run, (None, [3], DecayedScene(), None), cfg, CV())
    assert row["reacquisitions"] == 0 and row["objects_with_orbit"] == 0
    for k in ("completeness", "reacq_within_km", "rms_radial_km", "rms_intrack_km", "rms_crosstrack_km", "realism_95",
              "realism_mean_d2", "nn_in_gate_share", "time_to_orbit_s"):
        assert np.isnan(row[k]), k
    assert row["cross_tags_per_1e4"] == 625.0  # the returns are scored all the same


def test_time_to_orbit_counts_object_zero():
    """Object 0 (a valid id) first detected at 10 s, re-acquired from its pass ending at 400 s: 390 s; clutter
    (origin -1) is no object."""
    from hypotrack.experiments.ssa_breakup import scorecard as card

    run = SimpleNamespace(returns=pd.DataFrame(dict(scan=[0, 1, 2], origin=[-1, 0, 0], label=[1, 0, 0])))
    reacq = pd.DataFrame(dict(target=[0], t_end=[400.0], within=[True]))
    assert card._time_to_orbit(run, reacq, [0.0, 10.0, 400.0]) == (390.0, 1)


def test_a_neighbour_on_the_gate_boundary_is_inside():
    """σ = 1 km: object 1's neighbour at d² = 4.5625 / (3 + 1) = 1.140625 exactly (S = 4 I, Cholesky 2 I), and the
    gate probability whose χ²₃ quantile is 1.140625 exactly: on the boundary, inside (d² ≤ γ)."""
    p = chi2.cdf(1.140625, 3)
    assert chi2.ppf(p, 3) == 1.140625  # the quantile round-trips exactly (checked, not assumed)
    r = reacquisitions(SimpleNamespace(ends=_ends()), _scene(), CV(), 1.0, p, 1.25)
    assert r["nn_in_gate"].tolist() == [True, False, False]
