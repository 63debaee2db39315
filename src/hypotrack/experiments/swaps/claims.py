"""The ledger rows of document 003 Figs 5.1–5.3, from the swap curves and rates of :mod:`.run`."""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim
from ...reporting.verdict import with_control
from .run import swap_curve

__all__ = ["swap_claims"]


def swap_claims(curves: pd.DataFrame, rates: pd.DataFrame, *, distance: float, n_sensors: int) -> list:
    """Ledger rows of Figs 5.1–5.3: the RMS minimum near 4 swaps (3–5), the class-posterior peak
    within 3 swaps of it, the optimal swap rate 0.5 (± 1/N) at zero distance and 0 for the
    farthest distance simulated.

    Negative controls (each must fail its row's check): the RMS curve with the returns labelled by
    their true target instead of sorted (``curves['rms_labelled']``: no sorting bias for swaps to
    undo); the single-hypothesis posterior (Eq. 5.22 without the class count ``ln C(N, i)``); the
    GNNF paradigm that never swaps (rate 0) at zero distance; coincident targets (the smallest
    distance) under the far-distance check."""
    c = swap_curve(curves, distance)
    swaps = c["swaps"].to_numpy()
    i_min = int(swaps[np.argmin(c["rms"].to_numpy())])
    i_cls = int(swaps[np.argmax(c["log_prob_class"].to_numpy())])
    i_single = int(swaps[np.argmax(c["log_prob_single"].to_numpy())])
    r = rates.set_index("distance").sort_index()
    near, far = r["rms_optimal_rate"].iloc[0], r.index.max()
    ev = "published number"
    rows = []
    claim = Claim("swaps", "Fig 5.1 RMS minimum at about 4 swaps", "003 Sec. 5, Fig 5.1", "about 4", str(i_min),
                  "3-5 swaps", "reproduced" if 3 <= i_min <= 5 else "not reproduced",
                  f"RMS {c['rms'].iloc[0]:.3g} m with no swaps, {c['rms'].min():.3g} m at the minimum", ev,
                  key="rms_minimum")
    if "rms_labelled" in c:
        i_lab = int(swaps[np.argmin(c["rms_labelled"].to_numpy())])
        claim = with_control(claim, "returns labelled by their true target instead of sorted, the same swaps",
                             f"minimum at {i_lab} swaps", 3 <= i_lab <= 5)
    rows.append(claim)
    rows.append(with_control(
        Claim("swaps", "Fig 5.2 class posterior peak consistent with Fig 5.1", "003 Sec. 5, Fig 5.2",
              "consistent with about 4", str(i_cls), "within 3 of the RMS minimum",
              "reproduced" if abs(i_cls - i_min) <= 3 else "not reproduced",
              "the single-hypothesis curve peaks at 0 swaps (the MAP hypothesis has none)", ev, key="class_peak"),
        "the single-hypothesis posterior (Eq. 5.22 without the class count ln C(N, i))",
        f"peak at {i_single} swaps", abs(i_single - i_min) <= 3))
    rows.append(with_control(
        Claim("swaps", "Fig 5.3 optimal swap rate at zero distance", "003 Sec. 5, Fig 5.3", "0.5", f"{near:.3g}",
              f"+/- 1/{n_sensors}", "reproduced" if abs(near - 0.5) <= 1 / n_sensors + 1e-12 else "not reproduced",
              "", ev, key="rate_zero_distance"),
        "the GNNF paradigm (sorted returns, never swapped)", "rate 0", abs(0 - 0.5) <= 1 / n_sensors + 1e-12))
    closest = r.index.min()
    rows.append(with_control(
        Claim("swaps", "Fig 5.3 optimal swap rate for distant targets", "003 Sec. 5, Fig 5.3", "0",
              f"{r.loc[far, 'rms_optimal_rate']:.3g} at {far:g} m", "exact",
              "reproduced" if r.loc[far, "rms_optimal_rate"] == 0 else "not reproduced",
              f"first zero at {r.index[r['rms_optimal_rate'] == 0].min():g} m", ev, key="rate_far"),
        f"the same criterion on targets {closest:g} m apart", f"rate {r.loc[closest, 'rms_optimal_rate']:.3g}",
        bool(r.loc[closest, "rms_optimal_rate"] == 0)))
    return rows

