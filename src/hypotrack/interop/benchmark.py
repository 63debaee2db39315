"""Overhead of the Stone Soup adapter over hypotrack's own API (a measurement, not a test).

One Stone Soup scenario (``MultiTargetGroundTruthSimulator`` + ``SimpleDetectionSimulator``,
``n_targets`` known objects crossing a square, Poisson clutter) is simulated once. For each
algorithm, the same scans are tracked twice, alternating, ``repeats`` times:

* **own API** — hypotrack models built directly, the scans as numpy arrays prepared beforehand,
  ``tracker.step`` per scan (what a hypotrack user times);
* **adapter** — :class:`hypotrack.interop.stonesoup.HypotrackTracker` iterated over the recorded
  Stone Soup detections: the detections → array conversion, the tracker step and the Stone Soup
  ``Track``/``GaussianState`` output.

The overhead is ``min(adapter) / min(own) − 1`` (minimum over repeats: the least-disturbed run
of each on a shared machine), after one untimed warm-up run (numba compilation).
"""

from __future__ import annotations

import datetime
import time

import numpy as np
import pandas as pd

from .._validation import check_seed
from .stonesoup import _build, _region, translate_models

__all__ = ["adapter_overhead", "own_api_setup", "plot_overhead", "run_own_api", "simulate_scenario"]


def simulate_scenario(*, n_targets, n_scans, clutter_rate, p_D, q, half_width, seed):
    """Stone Soup models, the recorded scans ``[(time, set of detections)]`` and the priors."""
    from stonesoup.models.measurement.linear import LinearGaussian
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity
    from stonesoup.simulator.simple import MultiTargetGroundTruthSimulator, SimpleDetectionSimulator
    from stonesoup.types.state import GaussianState

    rng = np.random.default_rng(check_seed(seed))
    t0 = datetime.datetime(2025, 1, 1)
    transition = CombinedLinearGaussianTransitionModel(
        [ConstantVelocity(q, seed=seed + 1), ConstantVelocity(q, seed=seed + 2)])
    measurement = LinearGaussian(4, (0, 2), np.eye(2), seed=seed + 3)
    pos = rng.uniform(-0.5 * half_width, 0.5 * half_width, size=(n_targets, 2))
    vel = rng.normal(0.0, 1.0, size=(n_targets, 2))
    starts = [np.array([[p[0]], [v[0]], [p[1]], [v[1]]]) for p, v in zip(pos, vel)]
    truth = MultiTargetGroundTruthSimulator(
        transition, GaussianState(np.zeros((4, 1)), np.eye(4), timestamp=t0), timestep=datetime.timedelta(seconds=1),
        number_steps=n_scans, birth_rate=0.0, death_probability=0.0, preexisting_states=starts, seed=seed + 4)
    region = [[-half_width, half_width], [-half_width, half_width]]
    detector = SimpleDetectionSimulator(truth, measurement, meas_range=np.array(region, dtype=float),
                                        detection_probability=p_D, clutter_rate=clutter_rate, seed=seed + 5)
    scans = [(t, set(dets)) for t, dets in detector]
    prior_time = t0 - datetime.timedelta(seconds=1)
    priors = [GaussianState(s, np.diag([4.0, 1.0, 4.0, 1.0]), timestamp=prior_time) for s in starts]
    return transition, measurement, region, scans, priors


def own_api_setup(transition, measurement_model, region, scans, priors, p_D, clutter_rate):
    """The recorded scans as numpy arrays ``[(t, Z)]`` and ``build(algorithm, options)``, which
    constructs the hypotrack tracker from the translated models as a hypotrack user would."""
    motion, measurement, perm = translate_models(transition, measurement_model)
    means = np.array([np.ravel(s.state_vector)[perm] for s in priors])
    covs = np.array([np.asarray(s.covar)[np.ix_(perm, perm)] for s in priors])
    epoch = priors[0].timestamp
    arrays = []
    for t, dets in scans:
        Z = np.array([np.ravel(d.state_vector) for d in dets], dtype=float).reshape(-1, 2)
        arrays.append(((t - epoch).total_seconds(), Z[np.lexsort(Z.T[::-1])]))

    def build(algorithm, options):
        return _build(algorithm, motion, measurement, p_D, clutter_rate, _region(region, 2), means, covs,
                      dict(options))

    return arrays, build


def run_own_api(tracker, algorithm, arrays) -> None:
    """Step ``tracker`` through the scans, reading what a user reads (the MAP estimate of a filter)."""
    if algorithm in ("gnn", "jpda", "pdaf"):
        for t, Z in arrays:
            tracker.step(Z, t)
    else:
        for t, Z in arrays:
            _ = tracker.step(Z, t).map_estimate


def _own_api_seconds(algorithm, transition, measurement_model, region, scans, priors, p_D, clutter_rate, options):
    arrays, build = own_api_setup(transition, measurement_model, region, scans, priors, p_D, clutter_rate)
    tracker = build(algorithm, options)
    start = time.perf_counter()
    run_own_api(tracker, algorithm, arrays)
    return time.perf_counter() - start


def _adapter_seconds(algorithm, transition, measurement_model, region, scans, priors, p_D, clutter_rate, options):
    from .stonesoup import HypotrackTracker

    tracker = HypotrackTracker(
        transition_model=transition, measurement_model=measurement_model, algorithm=algorithm,
        detection_probability=p_D, clutter_rate=clutter_rate, clutter_region=region, detector=scans,
        initial_states=priors, options=options)
    start = time.perf_counter()
    for _ in tracker:
        pass
    return time.perf_counter() - start


def adapter_overhead(algorithms: dict, *, n_targets=10, n_scans=50, clutter_rate=10.0, p_D=0.9, q=0.05,
                     half_width=100.0, repeats=3, seed=0) -> pd.DataFrame:
    """Seconds per run of the own API and of the adapter, and the relative overhead, per algorithm.

    ``algorithms`` maps an algorithm name (:data:`hypotrack.interop.stonesoup.ALGORITHMS`) to its
    hypotrack options.
    """
    transition, measurement, region, scans, priors = simulate_scenario(
        n_targets=n_targets, n_scans=n_scans, clutter_rate=clutter_rate, p_D=p_D, q=q, half_width=half_width,
        seed=seed)
    args = (transition, measurement, region, scans, priors, p_D, clutter_rate)
    rows = []
    for algorithm, options in algorithms.items():
        # Warm-up, untimed: numba compiles the association kernels on first use.
        _own_api_seconds(algorithm, *args, dict(options))
        own, adapted = [], []
        for _ in range(repeats):  # alternate, so a load change hits both
            own.append(_own_api_seconds(algorithm, *args, dict(options)))
            adapted.append(_adapter_seconds(algorithm, *args, dict(options)))
        rows.append({
            "algorithm": algorithm, "n_targets": n_targets, "n_scans": n_scans, "clutter_rate": clutter_rate,
            "own_api_ms_per_scan": 1e3 * min(own) / n_scans, "adapter_ms_per_scan": 1e3 * min(adapted) / n_scans,
            "overhead": min(adapted) / min(own) - 1.0,
        })
    return pd.DataFrame(rows)


def plot_overhead(table: pd.DataFrame, pdf, png, target: float = 0.2) -> None:
    """Per-scan time of the own API and through the adapter, and the overhead against its target."""
    from ..reporting import figure_style

    fig, (ax, ax2) = figure_style.subplots(1, 2, height=3.4)
    x = np.arange(len(table))
    ax.bar(x - 0.2, table["own_api_ms_per_scan"], 0.4, label="hypotrack API (numpy scans)")
    ax.bar(x + 0.2, table["adapter_ms_per_scan"], 0.4, label="Stone Soup adapter")
    ax.set_yscale("log")
    ax.set_xticks(x, table["algorithm"])
    ax.set_ylabel("time per scan (ms)")
    ax.set_title(f"{table['n_targets'].iloc[0]} objects,\n{table['clutter_rate'].iloc[0]:g} clutter returns/scan")
    ax2.bar(x, 100 * table["overhead"], color="tab:gray")
    ax2.axhline(100 * target, color="tab:red", ls="--", label=f"target {100 * target:.0f} %")
    ax2.set_xticks(x, table["algorithm"])
    ax2.set_ylabel("adapter overhead\n(% of the tracker's own time)")
    ax2.set_title("Detections in, Stone Soup tracks out")
    figure_style.legend_below(fig, ncol=2)
    fig.suptitle("Cost of running hypotrack's trackers inside Stone Soup\n(machine- and load-dependent)")
    figure_style.save(fig, pdf, png, width=1.0, dpi=120)
