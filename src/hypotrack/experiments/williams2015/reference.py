"""The PMBM paper's own filter, run as a peer under GNU Octave on this project's scans.

García-Fernández, Williams, Granström & Svensson (2018) published their MATLAB code
(``Agarciafernandez/MTT``, ``PMBM filter/``). This module exports a shard's scans to CSV, runs the
project's driver ``workflows/scripts/williams2015_reference.m`` on a working copy of that code under
Octave, and reads back the per-scan estimates and CPU times, so that the reference and this project's
trackers are scored by the same GOSPA on identical returns (Octave's random streams are not MATLAB's:
implementations are compared on exported measurements, never on seeds).

The reference code is not part of this project: :func:`prepare_reference` copies it from a checkout
(``mtt_dir``) and the NRL Tracker Component Library (``tcl_dir``, the four ``.m`` files its ``.m``
fallback of ``kBest2DAssign`` needs) into a scratch folder, with one Octave fix: the pruning step's
``covPois(:,:,idx) = []`` fails in Octave when one Poisson component is left (a 2-D array), so it
becomes ``covPois = covPois(:,:,~idx)``, the same operation.
"""

from __future__ import annotations

import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["TCL_FILES", "octave_available", "reference_available", "export_scans", "prepare_reference",
           "run_reference", "read_estimates", "read_labels", "scenario_prelude", "SCENARIO_KEYS", "scenario_signature",
           "reference_estimates"]

#: The NRL Tracker Component Library files the reference's k-best assignment needs (paths in its checkout).
TCL_FILES = ("Assignment_Algorithms/k-Best_2D_Assignment/MurtyData.m", "Container_Classes/BinaryHeap.m",
             "Container_Classes/KeyVal.m", "Sample_Code/2D_Assignment/assign2DByCol.m")
PMBM_FILES = ("PoissonMBMtarget_update.m", "PoissonMBMtarget_estimate1.m", "PoissonMBMtarget_pruning.m",
              "PoissonMBMtarget_pred.m")
_PRUNING_FIX = ("filter_upd_pruned.covPois(:,:,index_remove)=[];",
                "filter_upd_pruned.covPois=filter_upd_pruned.covPois(:,:,~index_remove);")


def octave_available() -> bool:
    return shutil.which("octave") is not None


def reference_available(mtt_dir, tcl_dir) -> bool:
    """Whether Octave and both checkouts (with the files the driver needs) are present."""
    if not (octave_available() and mtt_dir and tcl_dir):
        return False
    mtt, tcl = Path(mtt_dir), Path(tcl_dir)
    return (all((mtt / "PMBM filter" / f).is_file() for f in PMBM_FILES) and (mtt / "Assignment" / "kBest2DAssign.m").is_file()
            and all((tcl / f).is_file() for f in TCL_FILES))


def export_scans(scans_by_run: dict, path) -> pd.DataFrame:
    """Write ``{run: [scan (m_k, 2), ...]}`` as CSV ``run,scan,x,y`` (scans 1-based; full precision)."""
    rows = [(r, k, z[0], z[1]) for r, scans in scans_by_run.items() for k, Z in enumerate(scans, start=1)
            for z in np.asarray(Z, dtype=float).reshape(-1, 2)]
    df = pd.DataFrame(rows, columns=["run", "scan", "x", "y"])
    df.to_csv(path, index=False, float_format="%.17g")
    return df


def prepare_reference(mtt_dir, tcl_dir, work) -> dict:
    """Copy the reference's PMBM filter and assignment folders and the TCL helpers into ``work``, with the
    Octave fix of the module docstring; returns the three folders for the driver's path."""
    work = Path(work)
    pmbm, assign, tcl = work / "pmbm", work / "assignment", work / "tcl"
    shutil.copytree(Path(mtt_dir) / "PMBM filter", pmbm, dirs_exist_ok=True)
    shutil.copytree(Path(mtt_dir) / "Assignment", assign, dirs_exist_ok=True)
    tcl.mkdir(parents=True, exist_ok=True)
    for f in TCL_FILES:
        shutil.copy(Path(tcl_dir) / f, tcl / Path(f).name)
    pruning = pmbm / "PoissonMBMtarget_pruning.m"
    text = pruning.read_text(encoding="latin-1")
    if _PRUNING_FIX[0] not in text:
        raise RuntimeError(f"{pruning}: the line the Octave fix replaces is not there (reference code changed?)")
    pruning.write_text(text.replace(*_PRUNING_FIX), encoding="latin-1")
    return {"pmbm_dir": pmbm, "assign_dir": assign, "tcl_dir": tcl}


def _octave_value(v) -> str:
    if isinstance(v, (str, Path)):
        return "'" + str(v).replace("'", "''") + "'"
    a = np.asarray(v, dtype=float)
    if a.ndim == 0:
        return repr(float(a))
    if a.ndim == 1:
        return "[" + " ".join(repr(float(x)) for x in a) + "]"
    return "[" + "; ".join(" ".join(repr(float(x)) for x in row) for row in a) + "]"


def scenario_prelude(model, lambda0: float) -> dict:
    """The driver's scenario variables from :class:`.scenario.Williams2015` (birth in the reference's
    ``[x, vx, y, vy]`` order; ``lambda0``: the reference's prior Poisson weight at time 0)."""
    order = [0, 2, 1, 3]  # [x, y, vx, vy] -> [x, vx, y, vy]
    region = model.sensor.clutter.region
    return {"n_steps": model.n_steps, "side": float(np.asarray(region.high)[0] - np.asarray(region.low)[0]),
            "clutter_rate": model.sensor.clutter.rate, "p_d": model.sensor.detection.p_D, "p_s": model.p_survive,
            "q": model.motion.q, "sigma_r": float(np.sqrt(model.sensor.measurement.R[0, 0])),
            "birth_weight": model.birth_weight, "birth_mean": model.birth_mean[order],
            "birth_cov": model.birth_cov[np.ix_(order, order)], "lambda0": float(lambda0)}


def run_reference(scans_by_run: dict, model, driver, mtt_dir, tcl_dir, lambda0: float = 3.0, timeout: float = 3600.0):
    """Run the reference PMBM filter under Octave on ``{run: scans}``; returns ``(estimates, times)``:
    ``run,scan,label,x,y`` per estimated object (``label``: its Bernoulli component's tag) and
    ``run,scan,cpu_s`` per scan."""
    if not reference_available(mtt_dir, tcl_dir):
        raise RuntimeError("the reference needs GNU Octave and checkouts of Agarciafernandez/MTT (mtt_dir) and the "
                           f"NRL Tracker Component Library (tcl_dir); got mtt_dir={mtt_dir!r}, tcl_dir={tcl_dir!r}")
    with tempfile.TemporaryDirectory(prefix="williams2015_reference_") as tmp:
        tmp = Path(tmp)
        paths = prepare_reference(mtt_dir, tcl_dir, tmp / "code")
        export_scans(scans_by_run, tmp / "scans.csv")
        pd.DataFrame({"run": list(scans_by_run)}).to_csv(tmp / "runs.csv", index=False)
        variables = {**paths, "scans_file": tmp / "scans.csv", "runs_file": tmp / "runs.csv",
                     "out_file": tmp / "estimates.csv", "time_file": tmp / "times.csv", **scenario_prelude(model, lambda0)}
        prelude = " ".join(f"{k} = {_octave_value(v)};" for k, v in variables.items())
        cmd = ["octave", "--no-gui", "--no-window-system", "-q", "--eval", f"{prelude} source({_octave_value(driver)});"]
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        if proc.returncode != 0:
            raise RuntimeError(f"octave failed (exit {proc.returncode}):\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}")
        return pd.read_csv(tmp / "estimates.csv"), pd.read_csv(tmp / "times.csv")


def read_estimates(estimates: pd.DataFrame, run: int, n_steps: int) -> list[np.ndarray]:
    """The positions ``(n_k, 2)`` estimated at each step ``1 .. n_steps`` of one run."""
    e = estimates[estimates.run == run]
    return [e.loc[e.scan == k, ["x", "y"]].to_numpy(dtype=float) for k in range(1, n_steps + 1)]


def read_labels(estimates: pd.DataFrame, run: int, n_steps: int) -> list[np.ndarray]:
    """The labels ``(n_k,)`` of the estimates at each step (the reference's Bernoulli tags; column ``label``)."""
    e = estimates[estimates.run == run]
    return [e.loc[e.scan == k, "label"].to_numpy(dtype=np.int64) for k in range(1, n_steps + 1)]


#: The config keys that decide the scans a run sees (with the master seed): a record is valid for them only.
SCENARIO_KEYS = ("n_steps", "n_objects", "side", "sigma_r", "q", "mid_variance", "p_D", "p_S", "clutter_rate", "birth")


def scenario_signature(cfg, seed: int) -> dict:
    """What a reference record must have been made with: the master seed and the scenario's keys."""
    return {"seed": int(seed), **{k: cfg[k] for k in SCENARIO_KEYS}}


def reference_estimates(cfg, seed: int, driver, record_dir=None):
    """The reference's estimates and CPU times on runs ``0 .. reference.n_runs − 1`` of the scenario.

    Run under Octave when :func:`reference_available` (``source = "octave"``); otherwise read from the
    committed record (``reference.record``, its ``_timing.csv`` and ``_config.json`` beside it), which must
    have been made with this seed and scenario and hold these runs. Returns ``(estimates, times, source)``."""
    import json

    from .run import scans_of_run, truth_for

    ref = cfg["reference"]
    runs = list(range(int(ref["n_runs"])))
    if reference_available(ref.get("mtt_dir"), ref.get("tcl_dir")):
        model, truth = truth_for(cfg, seed)
        scans = {r: scans_of_run(model, truth, seed, r) for r in runs}
        est, times = run_reference(scans, model, driver, ref["mtt_dir"], ref["tcl_dir"])
        return est, times, "octave"
    record = Path(ref["record"]) if record_dir is None else Path(record_dir) / Path(ref["record"]).name
    sig = json.loads(record.with_name(record.stem + "_config.json").read_text())
    want = json.loads(json.dumps(scenario_signature(cfg, seed)))
    if sig != want:
        diff = sorted(k for k in set(sig) | set(want) if sig.get(k) != want.get(k))
        raise ValueError(f"reference record {record} was made with another scenario or seed (differs in {diff}); "
                         "rerun it under Octave (reference.mtt_dir, reference.tcl_dir) or use the record's settings")
    est = pd.read_csv(record)
    times = pd.read_csv(record.with_name(record.stem + "_timing.csv"))
    missing = sorted(set(runs) - set(times.run))
    if missing:
        raise ValueError(f"reference record {record} holds runs {sorted(set(times.run))}, not {missing}: "
                         f"reference.n_runs may be at most {times.run.nunique()} without Octave")
    return est[est.run.isin(runs)].reset_index(drop=True), times[times.run.isin(runs)].reset_index(drop=True), "record"
