"""Detection probability from the signal-to-noise ratio: object size → radar cross-section → SNR → p_D.

Three stated models, each with its source:

* **RCS of an object of size d** (characteristic length, m) at wavelength λ — the two asymptotes of
  the NASA size-estimation model (SEM; Xu, Stokely, Matney & Stansbery, "A statistical size estimation
  model for Haystack and HAX radar detections", IAC-05-B6.1.02, 2005), a conducting sphere's RCS:
  optical region ``σ = π d²/4`` (x = d/λ large), Rayleigh region ``σ = (9π⁵/4) d⁶/λ⁴`` (x small).
  The SEM tabulates a resonance curve for 0.12 < x < 2.835; here (a stated simplification) the two
  asymptotes are joined where they cross, ``σ = (π d²/4) min(1, 9 π⁴ (d/λ)⁴)``, crossing at
  ``x = 1/(√3 π) ≈ 0.184`` (the resonance peak, up to 4× above the optical value, is left out).
* **SNR** — the radar equation: for one radar, SNR ∝ σ / r⁴ (Skolnik, *Introduction to Radar
  Systems*, 3rd ed., ch. 2; Richards, *Fundamentals of Radar Signal Processing*, 2nd ed., ch. 2).
  It is referenced to a stated design point: an object of size ``ref_diameter_m`` at range
  ``ref_range_km`` is detected with probability ``ref_p_D`` (default 0.5 — the radar's *detection
  limit*, the size/range at which half the passes are seen), so
  ``SNR(d, r) = SNR_ref σ(d)/σ(d_ref) (r_ref/r)⁴``.
* **p_D from SNR** — a Swerling I target (slow Rayleigh fluctuation, the usual model of a tumbling
  fragment) with a square-law detector and a threshold set for a false-alarm probability ``P_FA`` per
  resolution cell: ``p_D = P_FA^{1/(1 + SNR)}`` (single-pulse Swerling 1: Richards, ch. 6, detection
  fundamentals; Skolnik, ch. 2),
  so ``SNR_ref = ln P_FA / ln p_ref − 1`` (P_FA = 10⁻⁶, p_ref = 0.5: SNR_ref = 18.93, 12.8 dB).

Sizes of the bundled objects. The TLE catalogue holds no sizes, so a stated assumption:
payloads (group ``active``) are ``payload_diameter_m`` (2 m: the order of a small-satellite bus and
its panels; optical at UHF and S-band), objects named ``R/B`` (rocket bodies) ``rocket_body_diameter_m``
(3 m), and debris follow the NASA standard breakup model's collision size law (Fengyun-1C, Cosmos 2251
and Iridium 33 were collisions: ``N(>L) ∝ L^−1.71``, :mod:`.sbm`) above ``debris_min_m`` = 0.1 m
(the catalogue's tracking limit in LEO): ``L = L_min U^{−1/1.71}``, with ``U`` drawn from a stream
keyed by the seed and the NORAD number (an object's size does not change with the selection).

The tracker's side does not know an object's size: its detection probability at a predicted range is
the marginal over its assumed size distribution, ``p̄_D(r) = E_d[p_D(SNR(d, r))]`` (the debris law by
quantile quadrature), see :class:`SnrTrackerDetection`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import check_finite_array, check_positive, check_probability

__all__ = ["rcs_sphere", "swerling1_p_detect", "SnrModel", "SizeModel", "SnrTrackerDetection",
           "attach_snr_detection", "UHF_SNR", "S_BAND_SNR"]


def rcs_sphere(d_m, wavelength_m) -> np.ndarray:
    """RCS (m²) of objects of size ``d_m`` (m) at wavelength ``wavelength_m`` (m): the SEM's optical and
    Rayleigh asymptotes joined where they cross, ``(π d²/4) min(1, 9 π⁴ (d/λ)⁴)`` (module docstring)."""
    d = np.asarray(d_m, dtype=float)
    if np.any(~np.isfinite(d)) or np.any(d <= 0):
        raise ValueError("d_m must be finite and > 0 (object sizes in metres)")
    lam = check_positive(wavelength_m, "wavelength_m")
    x = d / lam
    return np.pi * d**2 / 4 * np.minimum(1.0, 9 * np.pi**4 * x**4)


def swerling1_p_detect(snr, p_fa: float) -> np.ndarray:
    """``P_FA^{1/(1 + SNR)}``: Swerling I detection probability at linear SNR ``snr`` (≥ 0) and false-alarm
    probability ``p_fa`` in (0, 1) (single-pulse Swerling 1)."""
    s = np.asarray(snr, dtype=float)
    if np.any(~(s >= 0)):
        raise ValueError("snr must be >= 0 (linear signal-to-noise ratio)")
    p = check_probability(p_fa, "p_fa", low_open=True, high_open=True)
    return np.exp(np.log(p) / (1.0 + s))


@dataclass(frozen=True)
class SnrModel:
    """One radar's SNR and Swerling I p_D of an object of size d at range r (module docstring).

    Parameters
    ----------
    wavelength_m : float
        Radar wavelength (m), > 0 (UHF 435 MHz: 0.69 m; S-band 3 GHz: 0.1 m).
    ref_diameter_m, ref_range_km : float
        The design point: an object of this size at this range is detected with ``ref_p_D``; > 0.
    ref_p_D : float
        Detection probability at the design point, in (P_FA, 1).
    p_fa : float
        False-alarm probability per resolution cell, in (0, 1).
    """

    wavelength_m: float = 0.69
    ref_diameter_m: float = 0.1
    ref_range_km: float = 3000.0
    ref_p_D: float = 0.5
    p_fa: float = 1e-6

    def __post_init__(self):
        for name in ("wavelength_m", "ref_diameter_m", "ref_range_km"):
            check_positive(getattr(self, name), name)
        check_probability(self.p_fa, "p_fa", low_open=True, high_open=True)
        p = check_probability(self.ref_p_D, "ref_p_D", low_open=True, high_open=True)
        if not p > self.p_fa:
            raise ValueError(f"ref_p_D must lie in (p_fa, 1) = ({self.p_fa:g}, 1): at SNR 0 p_D = p_fa, "
                             f"got {self.ref_p_D!r}")

    @property
    def snr_ref(self) -> float:
        """Linear SNR at the design point: ``ln P_FA / ln p_ref − 1``."""
        return float(np.log(self.p_fa) / np.log(self.ref_p_D) - 1.0)

    def snr(self, d_m, range_km) -> np.ndarray:
        """Linear SNR ``SNR_ref σ(d)/σ(d_ref) (r_ref/r)⁴`` of sizes ``d_m`` (m) at ranges ``range_km``."""
        r = np.asarray(range_km, dtype=float)
        if np.any(~(r > 0)):
            raise ValueError("range_km must be > 0")
        ratio = rcs_sphere(d_m, self.wavelength_m) / rcs_sphere(self.ref_diameter_m, self.wavelength_m)
        return self.snr_ref * ratio * (self.ref_range_km / r) ** 4

    def p_detect(self, d_m, range_km) -> np.ndarray:
        """Swerling I ``p_D`` of objects of size ``d_m`` (m) at ranges ``range_km`` (broadcast)."""
        return swerling1_p_detect(self.snr(d_m, range_km), self.p_fa)


UHF_SNR = SnrModel()
"""The default radar's (UHF, λ = 0.69 m at 435 MHz): a 10-cm object at 3,000 km is at its detection limit
(p_D = 0.5), as the default field of view's range limit states (:mod:`.sensors`)."""

S_BAND_SNR = SnrModel(wavelength_m=0.1, ref_diameter_m=0.1, ref_range_km=3000.0)
"""An S-band fence (3 GHz): 10 cm at 3,000 km at the detection limit. At λ = 0.1 m a 10-cm object is in
the optical region (x = 1), where at UHF it is Rayleigh — so small debris is far brighter to it."""


@dataclass(frozen=True)
class SizeModel:
    """The stated sizes of catalogue objects (module docstring).

    Parameters
    ----------
    payload_diameter_m, rocket_body_diameter_m : float
        Size (m) of the ``active`` group's payloads and of objects named ``R/B``, > 0.
    debris_min_m : float
        Smallest debris size (m), > 0.
    debris_exponent : float
        β of ``N(>L) ∝ L^−β``, > 0 (1.71: the standard breakup model's collisions).
    debris_share : float
        The tracker's assumed share of debris among the objects it may see, in [0, 1] (the truth side
        uses each object's group).
    """

    payload_diameter_m: float = 2.0
    rocket_body_diameter_m: float = 3.0
    debris_min_m: float = 0.1
    debris_exponent: float = 1.71
    debris_share: float = 0.5

    def __post_init__(self):
        for name in ("payload_diameter_m", "rocket_body_diameter_m", "debris_min_m", "debris_exponent"):
            check_positive(getattr(self, name), name)
        check_probability(self.debris_share, "debris_share")

    def sizes(self, catalogue, seed: int = 0) -> np.ndarray:
        """Size (m) of every object of a catalogue table (``group``, ``name``, ``norad`` columns)."""
        norad = np.asarray(catalogue["norad"], dtype=np.int64)
        group = np.asarray(catalogue["group"], dtype=object)
        name = np.asarray(catalogue["name"], dtype=object)
        d = np.full(len(norad), self.payload_diameter_m)
        rb = np.array(["R/B" in str(n) for n in name], dtype=bool)
        d[rb] = self.rocket_body_diameter_m
        deb = (group != "active") & ~rb
        # one uniform per object from a stream keyed by (seed, NORAD): the same size in every selection
        u = np.array([np.random.default_rng([int(seed), int(k)]).random() for k in norad[deb]])
        d[deb] = self.debris_min_m * (1.0 - u) ** (-1.0 / self.debris_exponent)
        return d

    def nodes(self, n: int = 64) -> tuple[np.ndarray, np.ndarray]:
        """``(sizes, weights)`` of the tracker's assumed distribution: the payload size with weight
        ``1 − debris_share`` and ``n`` midpoint quantiles ``L_min ((i + ½)/n)^{−1/β}`` of the debris law
        with weight ``debris_share / n`` each."""
        u = (np.arange(n) + 0.5) / n
        d = np.r_[self.payload_diameter_m, self.debris_min_m * u ** (-1.0 / self.debris_exponent)]
        w = np.r_[1.0 - self.debris_share, np.full(n, self.debris_share / n)]
        return d, w


def _r3(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


class SnrTrackerDetection:
    """A tracker sensor's detection with the marginal SNR p_D of a predicted state (module docstring).

    Wraps the ``detection`` of a tracker sensor (an object with ``radar``, ``theta`` and ``detection``:
    :class:`~.tracking.TrackerSensor`, :class:`~.radar_model.RadarTrackerSensor`): ``in_view`` is the
    wrapped one's; :meth:`p_D_of` is ``p̄_D(range)`` of TEME states, the marginal over ``sizes.nodes()``,
    tabulated on ``n_grid`` ranges over the field of view and interpolated linearly. ``p_D`` (the one
    number the engine's births and checks use) is ``p̄_D`` averaged over the field of view's physical
    volume (``r³`` uniform: where a birth at an unknown place is), and every value is clipped to
    ``[0, 1 − 10⁻⁹]`` (``log(1 − p_D)`` stays finite).
    """

    _CAP = 1.0 - 1e-9

    def __init__(self, owner, model: SnrModel, sizes: SizeModel = SizeModel(), *, n_grid: int = 512, n_nodes: int = 64):
        if not isinstance(model, SnrModel):
            raise TypeError(f"model must be an SnrModel, got {type(model).__name__}")
        if not isinstance(sizes, SizeModel):
            raise TypeError(f"sizes must be a SizeModel, got {type(sizes).__name__}")
        self._owner, self._base = owner, owner.detection
        fov = owner.radar.fov
        self.model, self.sizes = model, sizes
        self.ranges = np.linspace(max(fov.r_min_km, 1e-3), fov.r_max_km, n_grid)
        d, w = sizes.nodes(n_nodes)
        self.table = np.minimum(model.p_detect(d[None, :], self.ranges[:, None]) @ w, self._CAP)
        vol = self.ranges**2  # dV ∝ r² dr over the range interval
        self.p_D = float(np.trapezoid(self.table * vol, self.ranges) / np.trapezoid(vol, self.ranges))

    def in_view(self, z):
        return self._base.in_view(z)

    def p_D_of(self, states) -> np.ndarray:
        """``p̄_D`` ``(n,)`` at the ranges of TEME states ``(n, >= 3)`` from the site at the owner's GMST."""
        X = np.atleast_2d(np.asarray(states, dtype=float))
        if len(X) == 0:
            return np.zeros(0)
        site = self._owner.radar.site.ef
        rng = np.linalg.norm(X[:, :3] @ _r3(self._owner.theta).T - site, axis=1)
        return np.interp(rng, self.ranges, self.table)


def attach_snr_detection(sensor, model: SnrModel, sizes: SizeModel = SizeModel(), **kw):
    """Give a tracker sensor the SNR detection (:class:`SnrTrackerDetection`); returns the sensor."""
    sensor.detection = SnrTrackerDetection(sensor, model, sizes, **kw)
    return sensor


def check_sizes(sizes, n: int) -> np.ndarray:
    """``sizes`` as ``(n,)`` finite positive metres (``ValueError`` naming ``sizes`` otherwise)."""
    d = check_finite_array(sizes, "sizes", ndim=1)
    if len(d) != n or np.any(d <= 0):
        raise ValueError(f"sizes must hold one size > 0 (m) per catalogue object ({n}), got shape {d.shape}")
    return d
