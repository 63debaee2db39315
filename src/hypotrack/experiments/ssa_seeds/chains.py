"""SSA verdicts over chain seeds: the report's scenario held fixed, only R-FISST's MCMC stream varied.

A scenario-seed shard (:func:`.run.run_seed`) draws a new realisation *and* a new chain stream per
tracker, so the spread over scenario seeds mixes the two sources of randomness. A chain-seed shard
keeps the one realisation the report's single-run figures are drawn on — the ``ssa`` experiment's
scenario of the config's master seed (:func:`hypotrack.scenarios.ssa.scenario_from_config`, the tables
of rule ``ssa_scenario``) — and runs the same trackers with the same chain length as the scenario-seed
shards (``ssa_seeds.n_steps``) on it, each with its own stream: chain seed ``j`` of tracker ``t`` on
case ``c`` draws from ``experiment_seeds(seed, "ssa_seeds/c/chain/j/t", 1)[0]`` (disjoint from the
scenario-seed streams ``"ssa_seeds/c/i/t"``), so a chain seed's result does not depend on how many are
run. The spread over chain seeds is then the chain's own Monte Carlo error on that realisation — the
part of a verdict R-FISST's randomness, not the sky, decides.

Only the rows of R-FISST trackers (kind ``rfisst``: the ones drawing from their stream) and of the blind
tracker (the negative control) are kept; the deterministic trackers run as the references the R-FISST
rows are compared with.
"""

from __future__ import annotations

import io
from collections.abc import Callable, Mapping

import pandas as pd

from ..._validation import check_int
from ...scenarios.ssa import SSAScenario, params_from_config, prior_table, scenario_from_config
from ...scenarios.tables import write_table
from ..ssa import BLIND, scenario_from_tables
from .run import CASES, SEED_COLUMNS, run_case, tracker_settings

__all__ = ["CHAIN_COLUMNS", "chain_cases", "chain_scenario", "chain_stream", "run_chain_seed"]

#: One row per case, chain seed and tracker: the columns of :data:`.run.SEED_COLUMNS`, ``chain_index``
#: in place of ``seed_index``.
CHAIN_COLUMNS = [("chain_index" if c == "seed_index" else c) for c in SEED_COLUMNS]


def chain_cases(config: Mapping) -> dict:
    """``{case: number of chain seeds}`` of ``ssa_seeds.n_chain_seeds`` for the cases run over scenario
    seeds (absent or 0: none for that case)."""
    own = config["ssa_seeds"]
    counts = own.get("n_chain_seeds") or {}
    unknown = set(counts) - set(own["trackers"])
    if unknown:
        raise ValueError(f"ssa_seeds.n_chain_seeds names cases not in ssa_seeds.trackers {sorted(own['trackers'])}: "
                         f"{sorted(unknown)}")
    return {case: check_int(n, f"ssa_seeds.n_chain_seeds.{case}", minimum=0, maximum=10000)
            for case, n in counts.items() if n}


def chain_scenario(config: Mapping, case: str) -> SSAScenario:
    """The report's realisation of ``case`` as the report's trackers see it: drawn as rule ``ssa_scenario``
    draws it (``ssa`` section and master seed; ``ssa_seeds.n_scans`` does not apply: it would draw another
    realisation), then passed through the saved tables' number format and read back as the runs of rule
    ``ssa50_run`` / ``ssa15_run`` read it (:func:`~hypotrack.experiments.ssa.scenario_from_files`), so the
    returns are the same to the last bit."""
    if case not in CASES:
        raise ValueError(f"case must be one of {CASES}, got {case!r}")
    drawn = scenario_from_config(config, case)
    tables = []
    for table in (drawn.truth, drawn.scans, prior_table(drawn)):
        buffer = io.StringIO()
        write_table(table, buffer)
        tables.append(pd.read_csv(io.StringIO(buffer.getvalue())))
    return scenario_from_tables(params_from_config(config["ssa"], case), *tables)


def chain_stream(case: str, index: int, tracker: str) -> str:
    """The stream key of chain seed ``index`` of ``tracker`` on ``case``."""
    return f"ssa_seeds/{case}/chain/{check_int(index, 'index', minimum=0)}/{tracker}"


def run_chain_seed(config: Mapping, case: str, index: int, progress: Callable[[str], None] | None = print,
                   scenario: SSAScenario | None = None):
    """Chain seed ``index`` of ``case``: every configured tracker of the case on the report's realisation
    (:func:`chain_scenario`, or ``scenario`` when given: the pipeline passes rule ``ssa_scenario``'s tables
    read back), each from its :func:`chain_stream`.

    Returns ``(rows, timing)`` like :func:`.run.run_seed` with ``chain_index`` for ``seed_index``: rows of
    the R-FISST trackers and the blind tracker only (:data:`CHAIN_COLUMNS`); timing of every tracker run.
    """
    index = check_int(index, "index", minimum=0)
    scenario = chain_scenario(config, case) if scenario is None else scenario
    rows, timing = run_case(config, case, scenario, index, lambda name: chain_stream(case, index, name),
                            f"chain {index}", progress)
    kinds = {name: s.kind for name, s in tracker_settings(config, case).items()}
    rows = [r for r in rows if r["tracker"] == BLIND or kinds[r["tracker"]] == "rfisst"]
    rows = pd.DataFrame(rows, columns=SEED_COLUMNS).rename(columns={"seed_index": "chain_index"})
    return rows, pd.DataFrame(timing).rename(columns={"seed_index": "chain_index"})
