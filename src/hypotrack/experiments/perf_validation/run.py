"""What input validation costs (a measurement, not a test; the ``perf_validation`` rule).

hypotrack checks its input at the boundary (finite values, shapes, definiteness by Cholesky,
ranges) and keeps the batched inner paths unchecked. Two measurements show what that costs:

* **Kernels** — each public Gaussian function (:func:`hypotrack.gaussian.predict`, ``update``,
  ``innovation``, ``mahalanobis2_matrix``) against its unchecked private form on the same valid
  input, for batches of ``n`` tracks: the ratio is the price of calling the checked API.
* **Trackers** — the share of a tracker's per-scan time spent in the validation functions of
  :mod:`hypotrack._validation`. The calls a tracker makes during its steps are *recorded* (every
  ``check_*`` imported by a hypotrack module is wrapped for one run), then *replayed* alone and
  timed; the share is ``replay time / step time`` with the step time measured unwrapped. This is
  the regression the validation can cause in a tracking run: without any check the run could be
  at most that share faster.

Times are minima over ``repeats`` (the least-disturbed run on a shared machine), after an
untimed warm-up (numba compilation). Scenario: the Stone Soup simulation of
:mod:`hypotrack.interop.benchmark` (known objects crossing a square in Poisson clutter).
"""

from __future__ import annotations

import contextlib
import sys
import time

import numpy as np
import pandas as pd

from ... import _validation
from ... import gaussian as g
from ...interop.benchmark import own_api_setup, run_own_api, simulate_scenario

__all__ = ["kernel_overhead", "tracker_validation_share", "recorded_checks", "plot_validation_cost"]


def _seconds_per_call(fn, number: int) -> float:
    """Mean seconds per call over ``number`` calls."""
    t0 = time.perf_counter()
    for _ in range(number):
        fn()
    return (time.perf_counter() - t0) / number


def _kernel_calls(n: int, m: int, rng):
    """(name, checked call, unchecked call) on one valid batch of ``n`` tracks (d = 4, p = 2)."""
    dt = 1.0
    F = np.eye(4)
    F[0, 1] = F[2, 3] = dt
    Q = 0.1 * np.kron(np.eye(2), [[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    H = np.array([[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]])
    R = np.eye(2)
    x = rng.normal(size=(n, 4))
    A = rng.normal(size=(n, 4, 4))
    P = A @ np.swapaxes(A, -1, -2) + np.eye(4)
    z = x @ H.T + rng.normal(size=(n, 2))
    S = H @ P @ H.T + R
    zp = x @ H.T
    Z = rng.normal(size=(m, 2))
    return [
        ("predict", lambda: g.predict(x, P, F, Q), lambda: g.predict_unchecked(x, P, F, Q)),
        ("innovation", lambda: g.innovation(x, P, H, R), lambda: g.innovation_unchecked(x, P, H, R)),
        ("update", lambda: g.update(x, P, z, H, R), lambda: g.update_unchecked(x, P, z, H, R)),
        ("mahalanobis2_matrix", lambda: g.mahalanobis2_matrix(Z, zp, S), lambda: g.mahalanobis2_unchecked(Z, zp, S)),
    ]


def kernel_overhead(sizes=(1, 10, 100, 1000), *, n_returns: int = 20, repeats: int = 5, seed: int = 0,
                    target_seconds: float = 0.02) -> pd.DataFrame:
    """Microseconds per call of each checked Gaussian function and its unchecked form, and their ratio.

    Each measurement repeats the call enough times to last about ``target_seconds``.
    """
    rng = np.random.default_rng(seed)
    rows = []
    for n in sizes:
        for name, checked, unchecked in _kernel_calls(int(n), n_returns, rng):
            t1 = time.perf_counter()
            unchecked()
            number = max(1, int(target_seconds / max(time.perf_counter() - t1, 1e-7)))
            # Alternate the two forms within each repeat, so a load change hits both.
            checked()  # warm-up
            tc, tu = np.inf, np.inf
            for _ in range(repeats):
                tc = min(tc, _seconds_per_call(checked, number))
                tu = min(tu, _seconds_per_call(unchecked, number))
            rows.append({"kernel": name, "n_tracks": int(n), "n_returns": n_returns, "checked_us": 1e6 * tc,
                         "unchecked_us": 1e6 * tu, "ratio": tc / tu})
    return pd.DataFrame(rows)


def _check_functions() -> dict:
    return {name: f for name, f in vars(_validation).items() if name.startswith("check_") and callable(f)}


@contextlib.contextmanager
def recorded_checks():
    """Record every call of a :mod:`hypotrack._validation` check made through a hypotrack module.

    Yields the list that receives ``(function, args, kwargs)``. Each ``check_*`` imported into a
    loaded ``hypotrack`` module (not ``_validation`` itself, so nested checks are not counted
    twice) is replaced by a recording wrapper, and restored on exit.
    """
    calls = []
    originals = _check_functions()
    by_function = {id(f): f for f in originals.values()}
    patched = []

    def wrap(f):
        def recording(*args, **kwargs):
            calls.append((f, args, kwargs))
            return f(*args, **kwargs)
        return recording

    wrappers = {id(f): wrap(f) for f in originals.values()}
    try:
        for mod_name, mod in list(sys.modules.items()):
            if not mod_name.startswith("hypotrack") or mod is _validation or mod is None:
                continue
            for attr, value in list(vars(mod).items()):
                if id(value) in by_function and by_function[id(value)] is value:
                    setattr(mod, attr, wrappers[id(value)])
                    patched.append((mod, attr, value))
        yield calls
    finally:
        for mod, attr, value in patched:
            setattr(mod, attr, value)


def _replay_seconds(calls) -> float:
    """Seconds to make the recorded check calls again, alone."""
    t0 = time.perf_counter()
    for f, args, kwargs in calls:
        f(*args, **kwargs)
    return time.perf_counter() - t0


def tracker_validation_share(algorithms: dict, *, n_targets=10, n_scans=30, clutter_rate=10.0, repeats=3,
                             seed=0) -> pd.DataFrame:
    """Per-scan step time, time in validation checks (recorded and replayed) and their ratio, per tracker."""
    p_D = 0.9
    arrays, build = own_api_setup(*simulate_scenario(n_targets=n_targets, n_scans=n_scans, clutter_rate=clutter_rate,
                                                     p_D=p_D, q=0.05, half_width=100.0, seed=seed), p_D, clutter_rate)
    rows = []
    for algorithm, options in algorithms.items():
        run_own_api(build(algorithm, options), algorithm, arrays)  # warm-up (numba)
        tracker = build(algorithm, options)
        with recorded_checks() as calls:
            run_own_api(tracker, algorithm, arrays)
        run_s, check_s = np.inf, np.inf
        for _ in range(repeats):  # alternate, so a load change hits both
            tracker = build(algorithm, options)
            t0 = time.perf_counter()
            run_own_api(tracker, algorithm, arrays)
            run_s = min(run_s, time.perf_counter() - t0)
            check_s = min(check_s, _replay_seconds(calls))
        rows.append({"algorithm": algorithm, "n_targets": n_targets, "n_scans": n_scans, "clutter_rate": clutter_rate,
                     "check_calls_per_scan": len(calls) / n_scans, "step_ms_per_scan": 1e3 * run_s / n_scans,
                     "validation_ms_per_scan": 1e3 * check_s / n_scans, "validation_share": check_s / run_s})
    return pd.DataFrame(rows)


def plot_validation_cost(kernels: pd.DataFrame, trackers: pd.DataFrame, pdf, png, target: float = 0.05) -> None:
    """Left: checked/unchecked time per Gaussian kernel against batch size; right: each tracker's
    per-scan share spent in validation, against the target."""
    from ...reporting import figure_style

    fig, (ax, ax2) = figure_style.subplots(1, 2, height=3.4)
    for name, part in kernels.groupby("kernel", sort=False):
        ax.plot(part["n_tracks"], part["ratio"], "o-", label=name)
    ax.axhline(1.0, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("tracks in the batch")
    ax.set_ylabel("checked / unchecked time per call")
    ax.set_title("Public (checked) Gaussian functions\nvs their inner forms")
    x = np.arange(len(trackers))
    ax2.bar(x, 100 * trackers["validation_share"], color="tab:gray")
    ax2.axhline(100 * target, color="tab:red", ls="--", label=f"target {100 * target:.0f} %")
    ax2.set_xticks(x, trackers["algorithm"])
    ax2.set_ylabel("time in input checks\n(% of a scan's step)")
    ax2.set_title(f"Trackers: {trackers['n_targets'].iloc[0]} objects,\n"
                  f"{trackers['clutter_rate'].iloc[0]:g} clutter returns/scan")
    figure_style.legend_below(fig, ncol=2)
    fig.suptitle("What input validation costs (machine- and load-dependent)")
    figure_style.save(fig, pdf, png, width=1.0, dpi=120)
