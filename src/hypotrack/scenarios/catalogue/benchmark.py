"""Measurements for the catalogue scenario: SGP4 propagation cost, and the two-body model's mismatch.

Neither is a test (DESIGN.md §8: speed lives in benchmarks, not in timed tests). Run::

    python -m hypotrack.scenarios.catalogue.benchmark

to print both for the whole bundled catalogue (10,855 objects).
"""

from __future__ import annotations

import time

import numpy as np
import pandas as pd

from ...models.orbit3d import TwoBodyOrbit3D
from .propagation import propagate, reference_epoch, sgp4_states, time_grid_jd
from .tle import check_catalogue, groups_in, load_catalogue, satrec_array, select_altitude, select_groups

__all__ = ["benchmark_propagation", "two_body_mismatch"]


def benchmark_propagation(
    cat: pd.DataFrame | None = None, *, n_epochs: int = 60, dt: float = 10.0, repeats: int = 3
):
    """Cost of SGP4 propagation per (object, epoch) with ``SatrecArray.sgp4`` (best of ``repeats``).

    Parameters
    ----------
    cat : catalogue table; default the whole bundled catalogue (10,855 objects).
    n_epochs : epochs ``0, dt, ..., (n_epochs − 1) dt`` from the catalogue's epoch.
    repeats : timing repeats; the minimum is reported (the least disturbed by other load).

    Returns
    -------
    dict with ``n_objects``, ``n_epochs``, ``init_s`` (building the satellites from the TLE lines),
    ``propagate_s`` (one ``sgp4`` call over all pairs), ``us_per_object_epoch`` (that call),
    ``us_per_object_epoch_checked`` (with the plausibility check of :func:`.sgp4_states`, the
    scenario's path), ``us_per_object_init``.
    """
    cat = load_catalogue() if cat is None else check_catalogue(cat)
    if int(n_epochs) < 1 or int(repeats) < 1:
        raise ValueError(f"n_epochs and repeats must be >= 1, got {n_epochs!r}, {repeats!r}")
    jd, fr = time_grid_jd(reference_epoch(cat), np.arange(int(n_epochs)) * float(dt))
    a_mean = cat["semi_major_axis_km"].to_numpy(float)
    init, prop, checked = [], [], []
    for _ in range(int(repeats)):
        t0 = time.perf_counter()
        sats = satrec_array(cat)
        t1 = time.perf_counter()
        sats.sgp4(jd, fr)
        t2 = time.perf_counter()
        sgp4_states(sats, jd, fr, a_mean)
        t3 = time.perf_counter()
        init.append(t1 - t0)
        prop.append(t2 - t1)
        checked.append(t3 - t2)
    n = len(cat) * int(n_epochs)
    return {
        "n_objects": len(cat),
        "n_epochs": int(n_epochs),
        "init_s": min(init),
        "propagate_s": min(prop),
        "us_per_object_epoch": min(prop) / n * 1e6,
        "us_per_object_epoch_checked": min(checked) / n * 1e6,
        "us_per_object_init": min(init) / len(cat) * 1e6,
    }


def two_body_mismatch(cat: pd.DataFrame | None = None, dt: float = 10.0, start=None) -> pd.DataFrame:
    """One-step prediction error of the two-body model against SGP4.

    For every object: the SGP4 TEME state at ``start`` is propagated by ``dt`` with
    :class:`hypotrack.models.orbit3d.TwoBodyOrbit3D` and compared with SGP4 at ``start + dt``.

    Parameters
    ----------
    cat : catalogue table; default the LEO objects (perigee ≥ 200 km, apogee ≤ 2,000 km) of the
        whole bundled catalogue.
    dt : prediction interval (s).
    start : UTC date-time; default each group's own :func:`reference_epoch` (the elements are
        compared where they are valid: the 2021 debris in 2021, the active satellites in 2022).

    Returns
    -------
    DataFrame: ``norad``, ``group``, ``perigee_alt_km``, ``position_error_km``, ``velocity_error_km_s``
    (objects SGP4 cannot propagate at either time are left out).
    """
    cat = select_altitude(load_catalogue(), 200.0, 2000.0) if cat is None else check_catalogue(cat)
    if start is None:
        parts = [
            two_body_mismatch(select_groups(cat, g), dt, reference_epoch(select_groups(cat, g)))
            for g in groups_in(cat)
        ]
        return pd.concat(parts, ignore_index=True)
    p = propagate(cat, np.array([0.0, float(dt)]), start)
    ok = p.valid.all(axis=1)
    x0 = np.hstack([p.r[ok, 0], p.v[ok, 0]])
    x1 = TwoBodyOrbit3D().propagate(x0, float(dt))
    return pd.DataFrame(
        {
            "norad": p.norad[ok],
            "group": cat["group"].to_numpy()[ok],
            "perigee_alt_km": cat["perigee_alt_km"].to_numpy()[ok],
            "position_error_km": np.linalg.norm(x1[:, :3] - p.r[ok, 1], axis=1),
            "velocity_error_km_s": np.linalg.norm(x1[:, 3:] - p.v[ok, 1], axis=1),
        }
    )


def _main():  # pragma: no cover - a command-line report
    b = benchmark_propagation()
    print(
        f"SGP4 (SatrecArray), {b['n_objects']} objects x {b['n_epochs']} epochs: "
        f"{b['us_per_object_epoch']:.3f} us per object-epoch ({b['us_per_object_epoch_checked']:.3f} with the "
        f"plausibility check); initialisation {b['us_per_object_init']:.2f} us "
        "per object"
    )
    for dt in (10.0, 60.0):
        m = two_body_mismatch(dt=dt)
        e = m["position_error_km"] * 1e3
        v = m["velocity_error_km_s"] * 1e6
        print(
            f"two-body vs SGP4, {len(m)} LEO objects, dt = {dt:g} s: position error median {e.median():.3f} m, "
            f"99th pct {e.quantile(0.99):.3f} m, max {e.max():.3f} m; velocity error median {v.median():.3f} mm/s, "
            f"max {v.max():.3f} mm/s"
        )


if __name__ == "__main__":  # pragma: no cover
    _main()
