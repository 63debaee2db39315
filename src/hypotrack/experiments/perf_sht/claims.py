"""The perf_sht ledger rows (extensions): speed against Stone Soup and agreement with it on the same scans."""

from __future__ import annotations

import re

import pandas as pd

from ...reporting.ledger import Claim
from .run import BASELINE

__all__ = ["PEER_TOL", "perf_sht_claims"]


#: Largest difference from Stone Soup's outputs and states accepted as agreement (rounding only).
PEER_TOL = 1e-9


def perf_sht_claims(speedups: pd.DataFrame, largest: pd.DataFrame, timings: pd.DataFrame | None = None) -> list:
    """Ledger rows (extensions) for the speed of GNN/JPDA against Stone Soup, measured side by side, and
    (from ``timings``) the largest difference of their outputs (associations or marginals) and states on
    the same scans: the peer-implementation evidence that the timed trackers compute the same thing."""
    claims = []
    if timings is not None:
        for algorithm, g in timings.groupby("algorithm", sort=True):
            out, state = float(g["max_abs_output_diff"].max()), float(g["max_abs_state_diff"].max())
            claims.append(Claim(
                "perf_sht", f"{algorithm.upper()} agrees with Stone Soup on the timed scans", "extension",
                # the scans timed depend on the time budget, so the row states the bound, not the last digits
                "--", f"max |difference| below {PEER_TOL:g} (associations/marginals and states)"
                if max(out, state) <= PEER_TOL else f"max |difference| {max(out, state):.1e}", f"{PEER_TOL:g}",
                "extension" if max(out, state) <= PEER_TOL else "not reproduced",
                ", ".join(sorted(set(g["implementation"]) - {"hypotrack"})), "peer implementation",
                key=f"{algorithm}_peer_agreement"))
    for (algorithm, peer), g in speedups[speedups["goal"].notna()].groupby(["algorithm", "peer"]):
        goal = float(g["goal"].iloc[0])
        lo, hi = float(g["speedup"].min()), float(g["speedup"].max())
        if peer == BASELINE:  # the floor: hypotrack's time over the baseline's, at most 1 / goal
            slow = g["hypotrack_over_peer"]
            claims.append(Claim(
                "perf_sht", "GNN per-scan time over a minimal numpy + SciPy GNN doing the same work", "extension "
                "(speed-floor target)", f"<= {1 / goal:.3g}x", f"{slow.min():.2f}x to {slow.max():.2f}x",
                f"{int(g['n_targets'].min())}-{int(g['n_targets'].max())} targets", "extension",
                f"target {'met' if bool(g['goal_met'].all()) else 'not met'}; identical associations; same run",
                "measurement", key="GnnFloor"))
            continue
        met = bool((g["speedup"] >= goal).all())
        claims.append(Claim(
            "perf_sht", f"{algorithm.upper()} per-scan speed-up vs Stone Soup {peer}", "extension (speed-up target)",
            f">= {goal:g}x", f"{lo:.0f}x to {hi:.0f}x", f"{int(g['n_targets'].min())}-{int(g['n_targets'].max())} targets",
            "extension", f"target {'met' if met else 'not met'} at the goal's formation sizes; identical "
            "associations/marginals; ratios from one run, same scenarios", "measurement",
            key=f"{algorithm}_speedup_{re.sub('[^A-Za-z0-9]', '', peer)}"))
    lg = largest.set_index(["algorithm", "implementation"])
    for algorithm in sorted(largest["algorithm"].unique()):
        parts = [f"{impl}: {int(r.largest_cluster_tracks)}" for (alg, impl), r in lg.iterrows() if alg == algorithm]
        claims.append(Claim("perf_sht", f"largest {algorithm.upper()} cluster within 1 s per scan", "extension",
                            "--", "; ".join(parts), "--", "extension", "tracks in one cluster", "measurement",
                            key=f"{algorithm}_largest_cluster"))
    return claims

