"""Admissible-region birth: the Gaussian-mixture density of a new object given one radar return.

One return ``z = (ρ, az, el, ρ̇)`` (:mod:`.radar_model`) fixes the position and the range-rate of an
object but not its angle rates ``(α̇, ε̇) = (d az/dt, d el/dt)``. The **admissible region** is the set of
angle rates for which the state is a real object's: a bound orbit (``ε < 0``) whose perigee is at least
100 km up (Tommei, Milani & Rossi, "Orbit determination of space debris: admissible regions", *Celestial
Mechanics and Dynamical Astronomy* 97, 2007 — the radar case, unknowns the angle rates; Milani, Gronchi,
Vitturi & Knežević, *CMDA* 90, 2004 for the optical one). DeMars & Jah ("Probabilistic initial orbit
determination using Gaussian mixture models", *Journal of Guidance, Control, and Dynamics* 36(5), 2013)
represent the uniform density over that region by a Gaussian mixture and map it to the state space.

Construction (:class:`AdmissibleRegionBirth`)
--------------------------------------------
1. **State of an attributable.** ``y = (ρ, az, el, ρ̇, α̇, ε̇)`` gives the local line of sight
   ``l = ρ û(az, el)`` and its Earth-fixed rate ``l̇ = ρ̇ û + ρ (α̇ ∂û/∂az + ε̇ ∂û/∂el)``, and in TEME
   ``r = s + Mᵀ l``, ``v = Mᵀ l̇ + ω ẑ × r`` (``M = E R3(θ)``, ``s`` the site; :func:`attributable_to_state`,
   the inverse of the radar's ``h`` on its first four components).
2. **Box.** A bound orbit has ``|v| < v_esc(|r|)``; since ``∂û/∂az ⟂ ∂û/∂el ⟂ û`` with norms ``cos el`` and
   1, ``|ρ α̇ cos el|`` and ``|ρ ε̇|`` are at most ``V = sqrt((v_esc + |ω × r|)² − ρ̇²)``: the rate box.
3. **Grid.** The box is cut into ``n_blocks × n_blocks`` blocks of ``cells × cells`` cells. A cell is
   admissible when the orbit of its centre and of its four corners passes
   :func:`hypotrack.models.plausibility.plausible_orbits` (the return's measured values, noise-free).
4. **One Gaussian per block** (a cluster of admissible cells that is compact by construction): mean the
   centroid of its admissible cells' centres, covariance their scatter plus the cell's own
   ``diag(Δα̇², Δε̇²)/12`` (a uniform cell), times ``spread²``; weight ∝ its number of admissible cells
   (its area).
5. **To the state space.** Each component, with the return's noise ``R`` on ``(ρ, az, el, ρ̇)``, is mapped
   by the linearisation of step 1 (its Jacobian by complex step, exact to rounding): mean ``f(ȳ)``,
   covariance ``J diag(R, C_rates) Jᵀ``. Velocity is linear in the rates and ``ρ̇`` at a given position,
   so the map is exact but for the (small) angle and range noise.

Step 3's corner test and ``spread < 1`` keep the mixture's mass inside the region: the share of draws on
a plausible orbit is measured in the tests (``≥ 99 %``), against ~5 % for the zero-velocity birth
``N(0, (8 km/s)² I)`` of :class:`.OnePointBirth`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_finite_array, check_int, check_nonnegative, check_positive
from ...models.orbit import MU_EARTH
from ...models.plausibility import EARTH_RADIUS_PLAUSIBILITY, MIN_PERIGEE_ALTITUDE, plausible_orbits
from .admissible_grid import block_sums, segment_sums
from .admissible_kernels import admissible_components
from .frames import EARTH_ROTATION
from .radar_model import _H_STEP, RadarTrackerSensor, _r3, attributable_jacobian, attributable_to_state, site_teme

__all__ = ["attributable_to_state", "attributable_jacobian", "AdmissibleRegionBirth", "StateMixture", "SeededAdmissibleBirth"]


@dataclass(frozen=True, eq=False)
class StateMixture:
    """A Gaussian mixture in the TEME state space: ``weights`` (K,) summing to 1, ``means`` (K, 6),
    ``covs`` (K, 6, 6); ``rate_means`` (K, 2) and ``rate_covs`` (K, 2, 2) of its components in the angle-rate
    plane, and ``area`` the admissible region's area there (rad²/s²). A tracker's birth terms are its
    components (e.g. :class:`hypotrack.hypotheses.GaussianBirthTerm` ``(means[k], covs[k], H, R)`` with
    existence ``r_B × weights[k]``)."""

    weights: np.ndarray
    means: np.ndarray
    covs: np.ndarray
    rate_means: np.ndarray
    rate_covs: np.ndarray
    area: float

    def __len__(self) -> int:
        return len(self.weights)

    def sample(self, n: int, rng) -> np.ndarray:
        """``n`` draws ``(n, 6)`` (component by weight, then its Gaussian)."""
        k = rng.choice(len(self.weights), size=n, p=self.weights)
        L = np.linalg.cholesky(self.covs)
        return self.means[k] + np.einsum("nij,nj->ni", L[k], rng.standard_normal((n, 6)))


@dataclass(frozen=True, eq=False)
class AdmissibleRegionBirth:
    """The admissible-region birth density of a radar return (module docstring for the construction).

    Parameters
    ----------
    sensor : RadarTrackerSensor
        Site, azimuth window and noise ``R`` of the returns.
    n_blocks : int
        Blocks per axis of the rate box (at most ``n_blocks²`` components), >= 1; default 8.
    cells : int
        Cells per axis of a block, >= 1; default 8.
    spread : float
        Scale of each component's rate covariance, > 0; default 0.7 (keeps the mass inside the region).
    min_perigee_km : float
        Perigee floor (km) of an admissible orbit; default 100.
    compiled : bool
        :meth:`components_batch` in one compiled pass (:mod:`.admissible_kernels`; the same components to
        rounding), else in array passes; default true.
    """

    sensor: RadarTrackerSensor
    n_blocks: int = 8
    cells: int = 8
    spread: float = 0.7
    min_perigee_km: float = MIN_PERIGEE_ALTITUDE
    #: :meth:`components_batch` by the compiled kernel (:mod:`.admissible_kernels`), else in array passes
    compiled: bool = True

    def __post_init__(self):
        if not isinstance(self.sensor, RadarTrackerSensor):
            raise TypeError(f"sensor must be a RadarTrackerSensor, got {type(self.sensor).__name__}")
        object.__setattr__(self, "n_blocks", check_int(self.n_blocks, "n_blocks", minimum=1))
        object.__setattr__(self, "cells", check_int(self.cells, "cells", minimum=1))
        object.__setattr__(self, "spread", check_positive(self.spread, "spread"))

    def _plausible(self, z, azd, eld, theta):
        y = np.column_stack([np.broadcast_to(z, (azd.size, 4)), azd.ravel(), eld.ravel()])
        x = attributable_to_state(y, self.sensor.radar.site, theta)
        return plausible_orbits(x, min_perigee_km=self.min_perigee_km).reshape(azd.shape)

    def rate_box(self, z, theta) -> tuple[float, float]:
        """Half-widths ``(α̇_max, ε̇_max)`` (rad/s) of the rate box of return ``z`` (module docstring, step 2)."""
        rho, _, el, rd = z
        r = attributable_to_state(np.r_[z, 0.0, 0.0], self.sensor.radar.site, theta)[0, :3]
        rn = np.linalg.norm(r)
        V2 = (np.sqrt(2 * MU_EARTH / rn) + EARTH_ROTATION * np.hypot(r[0], r[1])) ** 2 - rd**2
        V = np.sqrt(max(V2, 0.0))
        return V / (rho * max(np.cos(el), 1e-6)), V / rho

    def region(self, z, theta=None):
        """The gridded admissible region of return ``z`` ``(4,)`` at GMST ``theta`` (default the sensor's):
        ``(az_rates (N,), el_rates (N,), admissible (N, N) bool)``, the cell centres (rad/s) and which cells
        are admissible (module docstring, steps 2–3; ``N = n_blocks · cells``, first axis the azimuth rate)."""
        z = check_finite_array(np.asarray(z, dtype=float), "z", shape=(4,))
        theta = self.sensor.theta if theta is None else float(theta)
        a_max, e_max = self.rate_box(z, theta)
        N = self.n_blocks * self.cells
        a_edges, e_edges = np.linspace(-a_max, a_max, N + 1), np.linspace(-e_max, e_max, N + 1)
        A, E = np.meshgrid(a_edges, e_edges, indexing="ij")
        corner = self._plausible(z, A, E, theta)
        ac, ec = (a_edges[:-1] + a_edges[1:]) / 2, (e_edges[:-1] + e_edges[1:]) / 2
        Ac, Ec = np.meshgrid(ac, ec, indexing="ij")
        ok = self._plausible(z, Ac, Ec, theta) & corner[:-1, :-1] & corner[1:, :-1] & corner[:-1, 1:] & corner[1:, 1:]
        return ac, ec, ok

    def mixture(self, z, theta=None) -> StateMixture:
        """The birth mixture of return ``z`` ``(4,)`` at GMST ``theta`` (default the sensor's current one).

        Raises ``ValueError`` when no cell is admissible (a return no bound orbit above the floor can give,
        e.g. a range-rate above the escape speed)."""
        z = check_finite_array(np.asarray(z, dtype=float), "z", shape=(4,))
        theta = self.sensor.theta if theta is None else float(theta)
        site = self.sensor.radar.site
        ac, ec, ok = self.region(z, theta)
        if not ok.any():
            raise ValueError(f"no admissible angle rates for return z = {z.tolist()} (no bound orbit with perigee "
                             f">= {self.min_perigee_km} km): check the range-rate and the units (km, rad, km/s)")
        a_max, e_max = self.rate_box(z, theta)
        da, de = 2 * a_max / len(ac), 2 * e_max / len(ec)
        Ac, Ec = np.meshgrid(ac, ec, indexing="ij")
        cell_cov = np.diag([da**2, de**2]) / 12.0
        counts, rate_means, rate_covs = [], [], []
        c = self.cells
        for i in range(self.n_blocks):
            for j in range(self.n_blocks):
                blk = ok[i * c:(i + 1) * c, j * c:(j + 1) * c]
                if not blk.any():
                    continue
                pts = np.column_stack([Ac[i * c:(i + 1) * c, j * c:(j + 1) * c][blk],
                                       Ec[i * c:(i + 1) * c, j * c:(j + 1) * c][blk]])
                mu = pts.mean(axis=0)
                d = pts - mu
                counts.append(len(pts))
                rate_means.append(mu)
                rate_covs.append((d.T @ d / len(pts) + cell_cov) * self.spread**2)
        counts = np.asarray(counts, dtype=float)
        rate_means, rate_covs = np.asarray(rate_means), np.asarray(rate_covs)
        means, covs = np.zeros((len(counts), 6)), np.zeros((len(counts), 6, 6))
        Cy = np.zeros((6, 6))
        Cy[:4, :4] = self.sensor.R
        for k in range(len(counts)):
            y = np.r_[z, rate_means[k]]
            Cy[4:, 4:] = rate_covs[k]
            J = attributable_jacobian(y, site, theta)
            means[k] = attributable_to_state(y, site, theta)[0].real
            P = J @ Cy @ J.T
            covs[k] = 0.5 * (P + P.T)
        return StateMixture(counts / counts.sum(), means, covs, rate_means, rate_covs, float(ok.sum() * da * de))

    def components_batch(self, Z, theta=None):
        """Every return's mixture in one vectorised pass: ``(weights (K,), means (K, 6), covs (K, 6, 6), owner
        (K,))`` for returns ``Z`` ``(m, 4)`` at GMST ``theta`` (default the sensor's), the components of
        :meth:`mixture` of return 0, then of return 1, ... (``owner[k]`` the return of component ``k``; a return
        with no admissible cell has none, where :meth:`mixture` raises). Equal to :meth:`mixture` return by
        return to rounding (the tests compare every weight, mean and covariance to 1e-12).

        With ``compiled`` one compiled pass (:func:`.admissible_kernels.admissible_components`), else
        :meth:`batch_parts` (steps 2-4 and the means) and :meth:`state_covs` (step 5's covariances)."""
        theta = self.sensor.theta if theta is None else float(theta)
        if self.compiled:
            Z = np.asarray(Z, dtype=float)
            Z = check_finite_array(Z.reshape(0, 4) if Z.size == 0 else Z, "Z", shape=(None, 4))
            if len(Z) == 0:
                return np.zeros(0), np.zeros((0, 6)), np.zeros((0, 6, 6)), np.zeros(0, dtype=np.int64)
            site = self.sensor.radar.site
            return admissible_components(Z, site_teme(site, theta)[0], site.enu @ _r3(theta), self.sensor.R,
                                         EARTH_ROTATION, MU_EARTH, MU_EARTH,
                                         EARTH_RADIUS_PLAUSIBILITY + self.min_perigee_km, self.n_blocks, self.cells,
                                         self.spread)
        w, means, owner, y, rate_covs = self.batch_parts(Z, theta)
        return w, means, self.state_covs(y, rate_covs, theta), owner

    def batch_parts(self, Z, theta=None):
        """:meth:`components_batch` but the covariances: ``(weights (K,), means (K, 6), owner (K,), y (K, 6),
        rate_covs (K, 2, 2))``, ``y`` each component's mean attributable ``(z, α̇, ε̇)`` and ``rate_covs`` its rate
        covariance, from which :meth:`state_covs` maps the covariances (a tracker that needs only the weights and
        the means, e.g. to decide which births can survive, skips their Jacobians).

        Steps 2-4 of the module docstring on arrays over all returns: one rate box per return, all their
        cells' corners and centres in one compiled pass (:func:`.admissible_grid.block_sums`, numpy's
        arithmetic in numpy's order: the same bits as :func:`plausible_orbits` of every grid state and
        numpy's sums over each block), and the components' means in one call of :func:`attributable_to_state`."""
        Z = np.asarray(Z, dtype=float)
        Z = check_finite_array(Z.reshape(0, 4) if Z.size == 0 else Z, "Z", shape=(None, 4))
        theta = self.sensor.theta if theta is None else float(theta)
        site, m, nb, c = self.sensor.radar.site, len(Z), self.n_blocks, self.cells
        N = nb * c
        if m == 0:
            return np.zeros(0), np.zeros((0, 6)), np.zeros(0, dtype=np.int64), np.zeros((0, 6)), np.zeros((0, 2, 2))
        # step 2 for every return (rate_box's arithmetic, one row per return)
        r = attributable_to_state(np.column_stack([Z, np.zeros((m, 2))]), site, theta)[:, :3]
        rn = np.sqrt(np.sum(r * r, axis=1))
        V2 = (np.sqrt(2 * MU_EARTH / rn) + EARTH_ROTATION * np.hypot(r[:, 0], r[:, 1])) ** 2 - Z[:, 3] ** 2
        V = np.sqrt(np.maximum(V2, 0.0))
        a_max, e_max = V / (Z[:, 0] * np.maximum(np.cos(Z[:, 2]), 1e-6)), V / Z[:, 0]
        # step 3: (m, N + 1) edges, (m, N) centres; corners and centres of all returns in one test
        a_edges = np.linspace(-a_max, a_max, N + 1, axis=1)
        e_edges = np.linspace(-e_max, e_max, N + 1, axis=1)
        ac, ec = (a_edges[:, :-1] + a_edges[:, 1:]) / 2, (e_edges[:, :-1] + e_edges[:, 1:]) / 2
        # step 1 is affine in the rates at a fixed return: x = x(z, 0, 0) + α̇ ∂x/∂α̇ + ε̇ ∂x/∂ε̇ (only the velocity
        # moves), so each return's three attributables give every cell's state (to rounding); steps 3-4 point by
        # point in one compiled pass, numpy's arithmetic in numpy's order (admissible_grid)
        base = attributable_to_state(np.column_stack([np.repeat(Z, 3, axis=0), np.tile(np.eye(3)[:, 1:], (m, 1))]),
                                     site, theta).reshape(m, 3, 6)
        sums = block_sums(base, a_edges, e_edges, ac, ec, nb, c, MU_EARTH, MU_EARTH**2,
                          EARTH_RADIUS_PLAUSIBILITY + check_nonnegative(self.min_perigee_km, "min_perigee_km"))
        ret, bi, bj = np.nonzero(sums[..., 0])
        cnt, s = sums[ret, bi, bj, 0], sums[ret, bi, bj]
        mu_a, mu_e = s[:, 1] / cnt, s[:, 2] / cnt
        cell_a, cell_e = (2 * a_max[ret] / N) ** 2 / 12.0, (2 * e_max[ret] / N) ** 2 / 12.0
        K = len(ret)
        rate_covs = np.empty((K, 2, 2))
        rate_covs[:, 0, 0] = (s[:, 3] / cnt + cell_a) * self.spread**2
        rate_covs[:, 1, 1] = (s[:, 4] / cnt + cell_e) * self.spread**2
        rate_covs[:, 0, 1] = rate_covs[:, 1, 0] = s[:, 5] / cnt * self.spread**2
        totals = np.bincount(ret, weights=cnt, minlength=m)
        y = np.column_stack([Z[ret], mu_a, mu_e])
        return cnt / totals[ret], attributable_to_state(y, site, theta), ret.astype(np.int64), y, rate_covs

    def state_covs(self, y, rate_covs, theta) -> np.ndarray:
        """Step 5's covariances ``(K, 6, 6)`` of components of mean attributables ``y`` ``(K, 6)`` and rate
        covariances ``rate_covs`` ``(K, 2, 2)`` at GMST ``theta``: ``J diag(R, C_rates) Jᵀ``, all ``K`` complex-step
        Jacobians (6 perturbed attributables each) in one call of :func:`attributable_to_state`."""
        y = np.asarray(y, dtype=float).reshape(-1, 6)
        K, site = len(y), self.sensor.radar.site
        Yc = np.repeat(y[:, None, :], 6, axis=1).astype(complex)
        Yc[:, np.arange(6), np.arange(6)] += 1j * _H_STEP
        J = np.swapaxes((attributable_to_state(Yc.reshape(-1, 6), site, theta).imag / _H_STEP).reshape(K, 6, 6), 1, 2)
        Cy = np.zeros((K, 6, 6))
        Cy[:, :4, :4] = self.sensor.R
        Cy[:, 4:, 4:] = rate_covs
        P = J @ Cy @ np.swapaxes(J, 1, 2)
        return 0.5 * (P + np.swapaxes(P, 1, 2))

    def components(self, z):
        """``(weights (K,), means (K, 6), covs (K, 6, 6))`` of :meth:`mixture` at the sensor's current GMST, and
        ``K = 0`` for a return no admissible orbit can give (a clutter return's range-rate above escape speed):
        the adaptive birth's per-return mixture (:class:`hypotrack.hypotheses.factored.AdaptiveBirth`)."""
        try:
            m = self.mixture(z)
        except ValueError:
            return np.zeros(0), np.zeros((0, 6)), np.zeros((0, 6, 6))
        return m.weights, m.means, m.covs


class SeededAdmissibleBirth:
    """The admissible region as the density of a track started at one return: HOMHT's births seeded at the
    returns (one option per component, :mod:`hypotrack.hypotheses.seeded`) and GNN/JPDA's mixture initiation
    (:class:`hypotrack.trackers.MOfNInitiator`).

    :meth:`components` is :meth:`AdmissibleRegionBirth.components` at the sensor's current GMST with the
    components whose **mean** fails the plausibility test dropped and the weights renormalised (a block's
    centroid can fall outside a non-convex region; a newborn's mean is then always a bound orbit above
    the floor), cached per (GMST, return): an engine asks for the same return's mixture once per parent
    hypothesis and again for each kept child's track. :meth:`admissible` is the region's test.
    :meth:`prime` fills the cache for a whole scan without the covariances, which the first :meth:`components`
    of a return maps (:meth:`component_weights` and :meth:`component_table`, the births' scores and the fast
    path's decision, need none): at scale most returns are a known object's, whose births no kept child holds.

    Parameters
    ----------
    region : AdmissibleRegionBirth
    cache_size : int
        Returns kept in the cache (cleared when the GMST changes, i.e. every scan, and when a return not in it
        is asked for with the cache full), >= 1; default 4096. A scan :meth:`prime` puts in the cache is kept
        whole, however many its returns (the cache's room grows to them until the GMST changes): at 10⁶ objects
        a scan has ~7,700 returns, and a cache of 4,096 cleared at every miss had most of them rebuilt one by
        one, several times a scan.
    """

    def __init__(self, region: AdmissibleRegionBirth, cache_size: int = 4096):
        if not isinstance(region, AdmissibleRegionBirth):
            raise TypeError(f"region must be an AdmissibleRegionBirth, got {type(region).__name__}")
        self.region = region
        self.cache_size = check_int(cache_size, "cache_size", minimum=1)
        self._theta, self._cache, self._room = None, {}, self.cache_size

    def admissible(self, states) -> np.ndarray:
        """Whether each state ``(n, 6)`` is a bound orbit with perigee above the region's floor."""
        return plausible_orbits(states, min_perigee_km=self.region.min_perigee_km)

    def components(self, z):
        """``(weights (K,), means (K, 6), covs (K, 6, 6))`` of return ``z`` ``(4,)`` (class docstring)."""
        w, means, covs, _ = self._entry(z, covs=True)
        return w.copy(), means.copy(), covs.copy()

    def component_weights(self, z):
        """``(weights (K,), means (K, 6))`` of :meth:`components` without the covariances: a return primed by
        :meth:`prime` has its covariances mapped only when :meth:`components` asks for them (the scores of its
        births and the test of their means need only these two; the engine asks for the track of a birth that a
        kept child holds, a few returns a scan)."""
        w, means, _, _ = self._entry(z, covs=False)
        return w.copy(), means.copy()

    def component_table(self, Z):
        """:meth:`component_weights` of every return ``Z`` ``(n, 4)`` at once: ``(K (n,) int64, weights (ΣK,), means
        (ΣK, 6))``, return 0's components first (the fast path's decision over a scan's lone tracks)."""
        Z = np.asarray(Z, dtype=float).reshape(-1, 4)
        entries = [self._entry(z, covs=False) for z in Z]
        K = np.array([len(e[0]) for e in entries], dtype=np.int64)
        if not len(entries):
            return K, np.zeros(0), np.zeros((0, 6))
        return K, np.concatenate([e[0] for e in entries]), np.concatenate([e[1] for e in entries])

    def _entry(self, z, covs: bool):
        """The cached ``[w, means, covs or None, (y, rate_covs) or None]`` of return ``z``, the covariances mapped
        now when ``covs`` and not yet (:meth:`AdmissibleRegionBirth.state_covs` of the kept components, the same
        map as the batch's; equal to it to rounding)."""
        z = np.asarray(z, dtype=float).reshape(4)
        theta = float(self.region.sensor.theta)
        if theta != self._theta:
            self._theta, self._cache, self._room = theta, {}, self.cache_size
        key = z.tobytes()
        entry = self._cache.get(key)
        if entry is None:
            if len(self._cache) >= self._room:  # full: start again (a return asked for is never dropped)
                self._cache = {}
            entry = self._cache[key] = [*self._kept(*self.region.components(z)), None]
        if covs and entry[2] is None:
            entry[2] = self.region.state_covs(*entry[3], theta)
        return entry

    def map_covariances(self, Z) -> int:
        """Map the covariances of returns ``Z`` ``(n, 4)`` not yet mapped at the current GMST in one call of
        :meth:`AdmissibleRegionBirth.state_covs` (their components' rows stacked), as :meth:`components` would map
        them one return at a time — the map is row by row, so each return's are the same numbers (the tests
        compare bit for bit) — for the engine steps of a scan's returns in no gate (HOMHT's seeded births,
        :mod:`hypotrack.hypotheses.factored.seeded_birth`), which each read one. Returns the returns mapped."""
        entries = [self._entry(z, covs=False) for z in np.asarray(Z, dtype=float).reshape(-1, 4)]
        todo = list({id(e): e for e in entries if e[2] is None}.values())  # (a return asked twice: once)
        if not todo:
            return 0
        y = np.concatenate([e[3][0] for e in todo])
        covs = self.region.state_covs(y, np.concatenate([e[3][1] for e in todo]), self._theta)
        cut = np.cumsum([0] + [len(e[3][0]) for e in todo])
        for e, a, b in zip(todo, cut[:-1], cut[1:]):
            e[2] = covs[a:b]
        return len(todo)

    def _kept(self, w, means, covs, ok=None):
        """The components whose mean passes :meth:`admissible` (``ok``, when already tested), weights
        renormalised (class docstring)."""
        if ok is None:
            ok = self.admissible(means) if len(w) else np.zeros(0, dtype=bool)
        w = w[ok]
        return w / w.sum() if len(w) else w, means[ok], covs[ok]

    def prime(self, Z) -> int:
        """Put the mixtures of a scan's returns ``Z`` ``(m, 4)`` into the cache in one batch
        (:meth:`AdmissibleRegionBirth.batch_parts`, at the sensor's current GMST), so that the engine's
        steps, each asking for the few returns of its gate, find them there. Returns the number computed.

        The batch equals :meth:`AdmissibleRegionBirth.mixture` return by return to rounding (the region's
        tests compare every weight, mean and covariance to 1e-12; on the catalogue's returns the largest
        relative difference is ~3e-15 and the admissible cells are the same): the component means are
        tested and the weights renormalised as for one return (:meth:`components`; each return's kept weights
        summed in numpy's order, :func:`.admissible_grid.segment_sums`). The covariances are left to the first
        :meth:`components` of the return (:meth:`component_weights`). Returns already cached at this GMST are
        not computed again; the cache's room grows to hold the whole scan (class docstring)."""
        Z = np.asarray(Z, dtype=float)
        Z = check_finite_array(Z.reshape(0, 4) if Z.size == 0 else Z, "Z", shape=(None, 4))
        theta = float(self.region.sensor.theta)
        if theta != self._theta:
            self._theta, self._cache, self._room = theta, {}, self.cache_size
        cache = self._cache
        keys = list(dict.fromkeys(k for k in (z.tobytes() for z in Z) if k not in cache))
        self._room = max(self._room, 2 * (len(cache) + len(keys)))  # the scan is kept whole (class docstring)
        if not keys:
            return 0
        new = np.frombuffer(b"".join(keys), dtype=float).reshape(len(keys), 4)
        w, means, owner, y, rate_covs = self.region.batch_parts(new, theta)
        ok = self.admissible(means)  # every component's mean in one test (one verdict per state)
        w, means, owner, y, rate_covs = w[ok], means[ok], owner[ok], y[ok], rate_covs[ok]
        cut = np.searchsorted(owner, np.arange(len(keys) + 1))
        w = w / np.repeat(segment_sums(w, cut), np.diff(cut))  # (w / w.sum() of each return's kept components)
        for i, key in enumerate(keys):
            s = slice(cut[i], cut[i + 1])
            cache[key] = [w[s], means[s], None, (y[s], rate_covs[s])]
        return len(keys)
