"""SSA experiments, step 1: the scenario rebuilt from the ``ssa`` rule's saved tables.

The trackers see exactly the saved data; :func:`catalogue_mask` says which objects the filter
could know of at each scan (the true number of objects of document 000 Fig. 11).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from ...models.orbit import TwoBodyOrbit
from ...scenarios.ssa import SSAParams, SSAScenario, params_from_config, read_prior, ssa_sensor
from ...scenarios.tables import state_columns, validate_scans, validate_truth

__all__ = ["catalogue_mask", "scenario_from_files", "scenario_from_tables", "truth_arrays"]


def scenario_from_tables(params: SSAParams, truth: pd.DataFrame, scans: pd.DataFrame,
                         prior: pd.DataFrame) -> SSAScenario:
    """The SSA scenario of the saved truth, scans and initial-hypothesis tables.

    Parameters
    ----------
    params : SSAParams
        The scenario's parameters (from the pipeline's ``ssa`` config section); they give the
        models — two-body motion, the FOV sensor — that generated the tables.
    truth, scans, prior : DataFrame
        Tables written by the ``ssa`` rule (:mod:`hypotrack.scenarios.tables`,
        :func:`hypotrack.scenarios.ssa.prior_table`).

    Returns
    -------
    SSAScenario

    Raises
    ------
    ValueError
        If the tables do not match ``params`` (number of scans or objects, scan times).
    """
    if not isinstance(params, SSAParams):
        raise TypeError(f"params must be an SSAParams, got {type(params).__name__}")
    truth = validate_truth(truth).sort_values(["scan", "target"], kind="stable").reset_index(drop=True)
    scans = validate_scans(scans)
    ids, means, covs = read_prior(prior)
    K, N = params.n_scans, params.n_objects
    targets = np.sort(truth["target"].unique())
    if not np.array_equal(targets, np.arange(N)) or len(truth) != K * N:
        raise ValueError(
            f"truth table must hold objects 0..{N - 1} at each of n_scans = {K} scans "
            f"(params), got {len(targets)} objects in {len(truth)} rows: regenerate the ssa tables"
        )
    times = truth["time"].to_numpy()[::N] if N else params.times
    if not np.allclose(times, params.times, rtol=0, atol=1e-9 * max(1.0, params.dt)):
        raise ValueError("truth table scan times differ from n_scans x dt of params: "
                         "regenerate the ssa tables")
    if len(ids) != params.n_known or np.any((ids < 0) | (ids >= N)):
        raise ValueError(f"prior table must hold n_known = {params.n_known} object ids in [0, {N}), "
                         f"got {ids}")
    in_view = truth["in_view"].to_numpy(dtype=bool).reshape(K, N)
    first = np.where(in_view.any(axis=0), in_view.argmax(axis=0), -1)
    return SSAScenario(
        params=params, times=params.times, truth=truth, scans=scans, prior_ids=ids, prior_means=means,
        prior_covs=covs, birth_ids=np.setdiff1d(np.arange(N), ids), first_in_view_scan=first,
        # The ssa module builds its sensor from the parameters with a private helper; using it
        # keeps one definition of the sensor (see the report: a public builder is requested).
        motion=TwoBodyOrbit(params.mu, params.q), sensor=ssa_sensor(params),
    )


def scenario_from_files(config: Mapping, case: str, truth, scans, prior) -> SSAScenario:
    """:func:`scenario_from_tables` from a pipeline config (its ``ssa`` section and ``case``,
    ``"ssa50"`` or ``"ssa15"``) and the paths of the saved tables."""
    params = params_from_config(config["ssa"], case)
    return scenario_from_tables(params, pd.read_csv(truth), pd.read_csv(scans), pd.read_csv(prior))


def truth_arrays(scenario: SSAScenario):
    """(K, N, 4) true states and (K, N) in-view flags (the truth table is complete)."""
    K, N = len(scenario.times), scenario.params.n_objects
    t = scenario.truth.sort_values(["scan", "target"], kind="stable")
    X = t[state_columns(4)].to_numpy(dtype=float).reshape(K, N, 4)
    return X, t["in_view"].to_numpy(dtype=bool).reshape(K, N)


def catalogue_mask(scenario: SSAScenario) -> np.ndarray:
    """(K, N) bool: objects the filter could know of at each scan.

    The objects of the initial hypothesis, and every other object from the first scan at which
    it is in the field of view on (the true number of objects of document 000 Fig. 11).
    """
    K, N = len(scenario.times), scenario.params.n_objects
    mask = np.zeros((K, N), dtype=bool)
    mask[:, scenario.prior_ids] = True
    for b in scenario.birth_ids:
        f = scenario.first_in_view_scan[b]
        if f >= 0:
            mask[f:, b] = True
    return mask
