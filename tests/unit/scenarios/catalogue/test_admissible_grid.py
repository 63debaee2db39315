"""The admissible region's grid in one compiled pass (:mod:`hypotrack.scenarios.catalogue.admissible_grid`) against
numpy: numpy's pairwise sum bit for bit (every length from 1 to 300 and past the 128-term halving), each grid
state's verdict bit for bit against :func:`plausible_orbits` (random states crowded at both edges of the region:
the energy's zero and the perigee floor), and each block's count, first and second moments against the numpy
construction (every corner and centre through :func:`plausible_orbits`, the blocks' masked sums) on returns whose
regions differ in shape and on random grids."""

import numpy as np
import pytest

from hypotrack.models.orbit import MU_EARTH
from hypotrack.models.plausibility import EARTH_RADIUS_PLAUSIBILITY, plausible_orbits
from hypotrack.scenarios.catalogue import DEFAULT_RADAR
from hypotrack.scenarios.catalogue.admissible import AdmissibleRegionBirth, attributable_to_state
from hypotrack.scenarios.catalogue.admissible_grid import _pairwise, _plausible, block_sums, segment_sums
from hypotrack.scenarios.catalogue.radar_model import RadarTrackerSensor

THETA = 0.4
C = DEFAULT_RADAR.fov.az_center
RP_MIN = EARTH_RADIUS_PLAUSIBILITY + 100.0


def test_pairwise_is_numpy_s_sum():
    for n in [*range(1, 300), 1000, 4097, 20011]:
        rng = np.random.default_rng(n)
        x = rng.standard_normal(n + 3) * 10.0 ** rng.integers(-6, 6, n + 3)
        assert 0.0 + _pairwise(x, 3, n) == x[3:].sum(), n  # (an offset start: a segment of a larger array)
        cut = np.r_[0, np.sort(rng.integers(0, n + 3, 4)), n + 3]
        np.testing.assert_array_equal(segment_sums(x, cut), [x[a:b].sum() for a, b in zip(cut[:-1], cut[1:])])


def test_each_verdict_is_plausible_orbits_bit_for_bit_at_both_edges():
    """States of random directions whose speed puts them within a few ulps of the escape speed or whose perigee
    is within a few ulps of the floor: the compiled verdict equals numpy's for every one (each side is hit)."""
    rng = np.random.default_rng(3)
    n = 20000
    r = rng.normal(size=(n, 3))
    r *= (rng.uniform(6500.0, 12000.0, n) / np.linalg.norm(r, axis=1))[:, None]
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    v_esc = np.sqrt(2 * MU_EARTH / np.linalg.norm(r, axis=1))
    speed = v_esc * (1 + rng.integers(-4, 5, n) * 2.0**-52)  # the energy's edge
    half = n // 2  # the other half: scan the speed for the perigee's edge (bisection on rp - RP_MIN)
    lo, hi = np.zeros(n - half), v_esc[half:] * 0.999
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        x = np.column_stack([r[half:], u[half:] * mid[:, None]])
        below = ~plausible_orbits(x) & (np.sum(x[:, 3:] ** 2, 1) / 2 - MU_EARTH / np.linalg.norm(r[half:], axis=1) < 0)
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    speed[half:] = hi * (1 + rng.integers(-4, 5, n - half) * 2.0**-52)
    X = np.column_stack([r, u * speed[:, None]])
    want = plausible_orbits(X)
    mu_r = MU_EARTH / np.sqrt((X[:, 0] * X[:, 0] + X[:, 1] * X[:, 1]) + X[:, 2] * X[:, 2])
    got = np.array([_plausible(*X[i, :3], mu_r[i], *X[i, 3:], MU_EARTH, MU_EARTH**2, RP_MIN) for i in range(n)])
    np.testing.assert_array_equal(got, want)
    assert 0.2 < want[:half].mean() < 0.8 and 0.2 < want[half:].mean() < 0.8  # both verdicts at both edges


def _numpy_blocks(region, Z, a_edges, e_edges):
    """Each block's sums by numpy on the grids of edges ``a_edges``, ``e_edges`` (m, N + 1): every corner and
    centre state through plausible_orbits, masked sums."""
    nb, c = region.n_blocks, region.cells
    m = len(Z)
    out = np.zeros((m, nb, nb, 6))
    site = region.sensor.radar.site
    for i, z in enumerate(Z):
        ae, ee = a_edges[i], e_edges[i]
        ac, ec = (ae[:-1] + ae[1:]) / 2, (ee[:-1] + ee[1:]) / 2
        base = attributable_to_state(np.column_stack([np.repeat(z[None], 3, 0), np.eye(3)[:, 1:]]), site, THETA)

        def verdict(a, e):
            A, E = np.meshgrid(a, e, indexing="ij")
            X = np.empty(A.shape + (6,))
            X[..., :3] = base[0, :3]
            X[..., 3:] = base[0, 3:] + A[..., None] * (base[1, 3:] - base[0, 3:]) + E[..., None] * (base[2, 3:] - base[0, 3:])
            return plausible_orbits(X)

        corner = verdict(ae, ee)
        ok = verdict(ac, ec) & corner[:-1, :-1] & corner[1:, :-1] & corner[:-1, 1:] & corner[1:, 1:]
        for bi in range(nb):
            for bj in range(nb):
                w = ok[bi * c:(bi + 1) * c, bj * c:(bj + 1) * c].astype(float)
                if not w.any():
                    continue
                A = np.repeat(ac[bi * c:(bi + 1) * c, None], c, 1)
                E = np.repeat(ec[None, bj * c:(bj + 1) * c], c, 0)
                cnt = w.sum()
                mu_a, mu_e = (A * w).sum() / cnt, (E * w).sum() / cnt
                da, de = (A - mu_a) * w, (E - mu_e) * w
                out[i, bi, bj] = [cnt, (A * w).sum(), (E * w).sum(), (da * da).sum(), (de * de).sum(), (da * de).sum()]
    return out


@pytest.mark.parametrize("n_blocks,cells", [(3, 8), (2, 5), (1, 24)])
def test_block_sums_are_the_numpy_construction(n_blocks, cells):
    region = AdmissibleRegionBirth(RadarTrackerSensor(DEFAULT_RADAR).at(THETA), n_blocks=n_blocks, cells=cells)
    rng = np.random.default_rng(n_blocks * 100 + cells)
    Z = np.column_stack([rng.uniform(300.0, 3000.0, 40), C + rng.uniform(-0.4, 0.4, 40),
                         np.deg2rad(rng.uniform(10.0, 80.0, 40)), rng.uniform(-7.0, 7.0, 40)])
    Z[0] = [1200.0, C, np.deg2rad(60.0), 15.0]  # above escape speed: no admissible cell
    N = n_blocks * cells
    site = region.sensor.radar.site
    m = len(Z)
    a_max, e_max = np.array([region.rate_box(z, THETA) for z in Z]).T
    ae, ee = np.linspace(-a_max, a_max, N + 1, axis=1), np.linspace(-e_max, e_max, N + 1, axis=1)
    base = attributable_to_state(np.column_stack([np.repeat(Z, 3, axis=0), np.tile(np.eye(3)[:, 1:], (m, 1))]),
                                 site, THETA).reshape(m, 3, 6)
    got = block_sums(base, ae, ee, (ae[:, :-1] + ae[:, 1:]) / 2, (ee[:, :-1] + ee[:, 1:]) / 2, n_blocks, cells,
                     MU_EARTH, MU_EARTH**2, RP_MIN)
    want = _numpy_blocks(region, Z, ae, ee)
    np.testing.assert_array_equal(got[..., 0], want[..., 0])  # the counts: every verdict the same
    np.testing.assert_array_equal(got[..., 1:3], want[..., 1:3])  # first moments: the same sums, bit for bit
    np.testing.assert_allclose(got[..., 3:], want[..., 3:], rtol=1e-13, atol=0)
    n_ok = want[..., 0].sum(axis=(1, 2))
    assert n_ok[0] == 0 and (n_ok > 0).sum() > 20 and ((want[..., 0] > 0) & (want[..., 0] < cells**2)).any()
