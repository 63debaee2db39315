"""perf_sht: hypotrack's GNN and JPDA against Stone Soup, same scenarios, one run, ratios.

Stone Soup is a benchmark/test-only dependency; its side of the benchmark is
:class:`hypotrack.interop.stonesoup.peer.StoneSoupPeer` (the ``step``/``record`` surface of
:class:`hypotrack.experiments.perf_sht.run.HypotrackStepper`), built here with Stone Soup's own
constant-velocity model; everything else is in :mod:`hypotrack.experiments.perf_sht`. Stone
Soup's state order is [x, vx, y, vy].
"""
import math

import numpy as np
import pandas as pd

from hypotrack.scenarios.tables import write_table
from hypotrack.trackers._sht_common import gate_tracks, predict_tracks
from hypotrack.experiments.perf_sht.figures import plot_benchmark
from hypotrack.experiments.perf_sht.run import (
    BASELINE,
    HypotrackStepper,
    NumpyGNNStepper,
    formation,
    largest_within,
    prior_covariance,
    scan_model,
    speedup_table,
)
from hypotrack.experiments.stepping import max_abs_difference, run_side_by_side
from hypotrack.interop.stonesoup.peer import StoneSoupPeer
from hypotrack.models import ConstantVelocity
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg_all = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
cfg = {**cfg_all["scenario"], **cfg_all["tracker"]}
PERM = [0, 2, 1, 3]  # hypotrack [x, y, vx, vy] -> Stone Soup [x, vx, y, vy]

try:
    import stonesoup  # noqa: F401

    HAVE_STONESOUP = True
except ImportError:
    HAVE_STONESOUP = False
    print("perf_sht: Stone Soup is not installed; timing hypotrack only", flush=True)


def stonesoup_peer(scenario, kind):
    """Stone Soup's ``kind`` on one scenario: Kalman predictor on its constant-velocity model per axis."""
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity as CV
    from stonesoup.predictor.kalman import KalmanPredictor

    predictor = KalmanPredictor(CombinedLinearGaussianTransitionModel([CV(cfg["q"]), CV(cfg["q"])]))
    n = len(scenario.initial_states)
    return StoneSoupPeer(kind, predictor, scan_model(scenario, cfg), (0, 2), scenario.initial_states,
                         np.broadcast_to(prior_covariance(cfg), (n, 4, 4)), scenario.scan_list(), perm=PERM)


def brute_force_products(scenario):
    """Joint products Stone Soup's brute-force JPDA enumerates at scan 1 (Π over tracks of 1 + gated)."""
    model = scan_model(scenario, cfg)
    n = len(scenario.initial_states)
    x, P = predict_tracks(ConstantVelocity(cfg["q"]), scenario.initial_states,
                          np.broadcast_to(prior_covariance(cfg), (n, 4, 4)), scenario.times[1] - scenario.times[0])
    valid = gate_tracks(x, P, scenario.scan_list()[1][1], model).valid
    return math.prod(int(1 + c) for c in valid.sum(axis=0))


def compare(algorithm, n, rate, peers, *, max_scans, budget_s, seed, spacing=None, warmup=True):
    sc = formation(n, rate, cfg if spacing is None else {**cfg, "spacing": spacing}, seed)
    steppers = {"hypotrack": HypotrackStepper(sc, algorithm, cfg)}
    if algorithm == "gnn" and BASELINE in peers:
        steppers[BASELINE] = NumpyGNNStepper(sc, cfg)  # the speed floor, same work, same process
    notes = {}
    for kind in [p for p in peers if p != BASELINE] if HAVE_STONESOUP else []:
        if kind == "JPDA":
            products = brute_force_products(sc)
            if products > cfg_all["jpda"]["brute_force_max_products"]:
                notes[kind] = f"not run: ~{products:.2e} joint products per scan"
                continue
        steppers[kind] = stonesoup_peer(sc, kind)
    runs = run_side_by_side(steppers, len(sc.times), max_scans=max_scans, budget_s=budget_s, warmup=warmup)
    rows = []
    for name, run in runs.items():
        d_out, d_state = max_abs_difference(runs["hypotrack"], run) if name != "hypotrack" else (0.0, 0.0)
        rows.append(dict(algorithm=algorithm, implementation=name, n_targets=n, clutter_rate=rate,
                         scans_timed=len(run.times), median_ms=run.median_ms,
                         mean_ms=1e3 * float(np.mean(run.times)) if run.times else np.nan,
                         max_cluster=runs["hypotrack"].max_cluster, max_abs_output_diff=d_out,
                         max_abs_state_diff=d_state, note=""))
        print(f"perf_sht {algorithm} n={n} clutter={rate:g} {name}: {run.median_ms:.3f} ms/scan "
              f"({len(run.times)} scans), diffs {d_out:.2e} / {d_state:.2e}", flush=True)
    for kind, note in notes.items():
        rows.append(dict(algorithm=algorithm, implementation=kind, n_targets=n, clutter_rate=rate, scans_timed=0,
                         median_ms=np.nan, mean_ms=np.nan, max_cluster=runs["hypotrack"].max_cluster,
                         max_abs_output_diff=np.nan, max_abs_state_diff=np.nan, note=note))
        print(f"perf_sht {algorithm} n={n} clutter={rate:g} {kind}: {note}", flush=True)
    return rows


seed = cfg_all["seed"]
rows = []
for n in cfg_all["gnn"]["n_targets"]:
    rows += compare("gnn", n, cfg_all["gnn"]["clutter_rate"], [BASELINE, "GNNWith2DAssignment"],
                    max_scans=cfg_all["max_scans"], budget_s=cfg_all["budget_s"], seed=seed)
for rate in cfg_all["jpda"]["clutter_rates"]:
    for n in cfg_all["jpda"]["n_targets"]:
        rows += compare("jpda", n, rate, ["JPDAwithEHM2", "JPDA"],
                        max_scans=cfg_all["max_scans"], budget_s=cfg_all["budget_s"], seed=seed)
timings = pd.DataFrame(rows)
ratios = speedup_table(timings, cfg_all["goals"], cfg_all.get("goal_n_targets"))

# Largest formation each implementation handles within the limit, at a spacing that chains the
# whole formation into one cluster. No warm-up scan and a budget of one limit: an
# implementation stops at the first scan that is over the limit.
big = cfg_all["largest"]
largest_rows = []
for algorithm, impls in (("gnn", ["hypotrack", "GNNWith2DAssignment"]), ("jpda", ["hypotrack", "JPDAwithEHM2", "JPDA"])):
    for impl in impls:
        if impl != "hypotrack" and not HAVE_STONESOUP:
            continue
        for n in big["n_targets"]:
            r = compare(algorithm, n, big["clutter_rate"], [] if impl == "hypotrack" else [impl],
                        max_scans=big["max_scans"], budget_s=big["limit_ms"] / 1e3, seed=seed,
                        spacing=big["spacing"], warmup=False)
            row = next(x for x in r if x["implementation"] == impl)
            largest_rows.append(row)
            if not np.isfinite(row["median_ms"]) or row["median_ms"] > big["limit_ms"]:
                break
largest_runs = pd.DataFrame(largest_rows)
largest = largest_within(largest_runs.dropna(subset=["median_ms"]), big["limit_ms"])

write_table(timings, snakemake.output.timings)  # noqa: F821
write_table(ratios, snakemake.output.speedups)  # noqa: F821
write_table(largest_runs, snakemake.output.largest_runs)  # noqa: F821
write_table(largest, snakemake.output.largest)  # noqa: F821
plot_benchmark(timings, ratios, snakemake.output.pdf, snakemake.output.png)  # noqa: F821
print(ratios.to_string(index=False), flush=True)
print(largest.to_string(index=False), flush=True)
