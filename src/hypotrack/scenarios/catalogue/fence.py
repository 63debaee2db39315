"""A fence sensor: a second site whose field of view is a thin band of elevations, crossed in a few scans.

:func:`space_fence` models a radar of the class of the US Space Force's Space Fence (Lockheed Martin,
S-band, operational 2020):

* **site** — Kwajalein Island, Republic of the Marshall Islands, 8.72° N, 167.73° E, 10 m (the Space Fence
  radar's island; Haimerl & Fonder, "Space Fence System Overview", AMOS 2015). Near the equator every
  orbit inclined above ~9° passes over it;
* **wavelength** — S-band, 3 GHz, λ = 0.10 m (same source); its SNR model is
  :data:`.snr.S_BAND_SNR` (a 10-cm object at 3,000 km at the detection limit — the size the Space Fence
  is stated to track in LEO);
* **field of view** — a *modelled* fence, not the real radar's beam layout (not public in detail): the
  full azimuth circle at elevations 20°–23°, ranges 200–4,000 km (4,000 km: the slant range to 2,000-km
  altitude at 20° elevation is 3,670 km). An object crosses the 3° band in a few 10-s scans: measured
  over the 6,789 bundled active satellites for 2 h from the default start (p_D = 1), 2.9 scans per
  crossing on average (median 2; 1,554 crossings of 845 objects) — a pass over the site crosses it twice;
* **revisit, noise, clutter** — as :data:`.sensors.DEFAULT_RADAR` (10 s: one scenario's sensors scan
  together, :func:`.simulate_catalogue`); p_D 0.9 unless an SNR model and sizes are used.
"""

from __future__ import annotations

from .sensors import GroundRadar, GroundSite, RadarFieldOfView
from .snr import S_BAND_SNR

__all__ = ["FENCE_SITE", "FENCE_FOV", "space_fence"]

FENCE_SITE = GroundSite(8.72, 167.73, 0.01, "Kwajalein Island")
"""The fence's site (module docstring)."""

FENCE_FOV = RadarFieldOfView(az_center_deg=0.0, az_width_deg=360.0, el_min_deg=20.0, el_max_deg=23.0,
                             r_min_km=200.0, r_max_km=4000.0)
"""The modelled fence: every azimuth, elevations 20°–23°, 200–4,000 km."""


def space_fence(*, snr: bool = False, **changes) -> GroundRadar:
    """The fence radar (module docstring); ``snr=True`` attaches :data:`.snr.S_BAND_SNR`; ``changes`` are
    any other :class:`.GroundRadar` fields (e.g. ``measurement="enu"``, ``p_D``, ``clutter_rate``)."""
    options = dict(site=FENCE_SITE, fov=FENCE_FOV, name="S-band fence", snr=S_BAND_SNR if snr else None)
    options.update(changes)
    return GroundRadar(**options)
