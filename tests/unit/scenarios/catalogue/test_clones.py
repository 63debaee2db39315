"""Cloned populations (hypotrack.scenarios.catalogue.clones): each clone keeps its parent's a, e, i (and
ω, drag, epoch) with only M and Ω shifted; offsets are fixed by the seed and the copy; the truth streamed in
chunks is the truth computed at once; a population of copy 0 alone simulates to simulate_catalogue's
scenario exactly."""

import numpy as np
import pandas as pd
import pytest
from sgp4.api import WGS72, Satrec

from hypotrack.scenarios.catalogue import DEFAULT_RADAR, load_catalogue, sample_objects, simulate_catalogue
from hypotrack.scenarios.catalogue.clones import (
    CLONE_ID_BASE,
    clone_population,
    clone_satrecs,
    clone_states,
    simulate_clones,
)
from hypotrack.scenarios.catalogue.propagation import reference_epoch, time_grid_jd


@pytest.fixture(scope="module")
def cat():
    return sample_objects(load_catalogue(), 40, seed=7).reset_index(drop=True)


def test_clones_keep_their_parents_shape_and_shift_only_m_and_raan(cat):
    pop = clone_population(cat, 130, seed=3)  # copy 0, two full copies and 10 objects of a third
    assert len(pop) == 130 and pop["copy"].tolist() == [0] * 40 + [1] * 40 + [2] * 40 + [3] * 10
    perm = pop["parent"].to_numpy()[:40]
    assert sorted(perm) == list(range(40)) and perm.tolist() != list(range(40))  # a seeded order of the catalogue
    np.testing.assert_array_equal(pop["parent"], np.tile(perm, 4)[:130])
    assert pop["norad"].is_unique and (pop["norad"][40:] >= CLONE_ID_BASE).all()
    pd.testing.assert_frame_equal(pop.iloc[:40][list(cat.columns)],
                                  cat.iloc[perm].reset_index(drop=True))  # copy 0 is the catalogue
    sats = clone_satrecs(pop, cat)
    par = [Satrec.twoline2rv(a, b) for a, b in zip(cat["line1"], cat["line2"])]
    recs = [Satrec.twoline2rv(a, b) if a else None for a, b in zip(pop["line1"], pop["line2"])]
    assert recs[40] is None  # a clone has no TLE
    # the records' mean elements: a (through n), e, i, ω, B* and the epoch are the parent's; M and Ω shifted
    e, r, v = sats.sgp4(np.array([par[0].jdsatepoch]), np.array([par[0].jdsatepochF]))
    assert r.shape == (130, 1, 3)
    for k in (41, 95, 125):
        p = par[pop.at[k, 'parent']]
        one = Satrec()
        dM, dO = pop.at[k, "d_mean_anomaly_rad"], pop.at[k, "d_raan_rad"]
        one.sgp4init(WGS72, "i", p.satnum, p.jdsatepoch - 2433281.5 + p.jdsatepochF, p.bstar, p.ndot, p.nddot,
                     p.ecco, p.argpo, p.inclo, np.mod(p.mo + dM, 2 * np.pi), p.no_kozai, np.mod(p.nodeo + dO, 2 * np.pi))
        assert (one.no_kozai, one.ecco, one.inclo, one.argpo, one.bstar) == (p.no_kozai, p.ecco, p.inclo, p.argpo,
                                                                             p.bstar)
        assert 0 < dM < 2 * np.pi and 0 < dO < 2 * np.pi
        _, r1, _ = one.sgp4(par[0].jdsatepoch, par[0].jdsatepochF)
        np.testing.assert_array_equal(r[k, 0], r1)
        # same semi-major axis in the table, and the orbit radius within the parent's perigee..apogee band
        assert pop.at[k, "semi_major_axis_km"] == cat.at[pop.at[k, 'parent'], "semi_major_axis_km"]
        assert pop.at[k, "inclination_deg"] == cat.at[pop.at[k, 'parent'], "inclination_deg"]
        assert pop.at[k, "eccentricity"] == cat.at[pop.at[k, 'parent'], "eccentricity"]
        rad = np.linalg.norm(r[k, 0])
        lo, hi = (cat.at[pop.at[k, 'parent'], c] + 6378.135 for c in ("perigee_alt_km", "apogee_alt_km"))
        assert lo - 30 < rad < hi + 30


def test_offsets_are_fixed_by_the_seed_and_the_copy(cat):
    a, b, c = clone_population(cat, 130, seed=3), clone_population(cat, 130, seed=3), clone_population(cat, 130, seed=4)
    pd.testing.assert_frame_equal(a, b)
    assert not np.array_equal(a["d_raan_rad"][40:], c["d_raan_rad"][40:])
    # a population is a prefix of every larger one (offsets depend on the copy, not on n)
    pd.testing.assert_frame_equal(clone_population(cat, 57, seed=3), a.iloc[:57])
    with pytest.raises(ValueError, match="n must be"):
        clone_population(cat, -1, seed=3)


def test_chunks_concatenate_to_the_unchunked_truth(cat):
    pop = clone_population(cat, 130, seed=3)
    jd, fr = time_grid_jd(reference_epoch(cat), np.arange(0.0, 600.0, 60.0))
    whole = list(clone_states(pop, cat, jd, fr, chunk=10**6))
    parts = list(clone_states(pop, cat, jd, fr, chunk=17))
    assert len(whole) == 1 and [p[0] for p in parts] == list(range(0, 130, 17))
    for i in (1, 2, 3):
        np.testing.assert_array_equal(np.concatenate([p[i] for p in parts]), whole[0][i])
    assert np.isfinite(whole[0][2]).all()


def test_copy_zero_simulates_to_simulate_catalogue(cat):
    b = simulate_clones(cat, len(cat), DEFAULT_RADAR, n_scans=30, seed=11, clone_seed=3, chunk=13)
    a = simulate_catalogue(cat.iloc[b.catalogue["parent"]].reset_index(drop=True), DEFAULT_RADAR, n_scans=30,
                           seed=11, start=reference_epoch(cat))
    pd.testing.assert_frame_equal(a.truth, b.truth)
    pd.testing.assert_frame_equal(a.scans, b.scans)
    np.testing.assert_array_equal(a.n_in_view, b.n_in_view)
    Xa, va = a.states([0.0, 60.0])
    Xb, vb = b.states([0.0, 60.0])
    np.testing.assert_array_equal(Xa, Xb)
    np.testing.assert_array_equal(va, vb)
