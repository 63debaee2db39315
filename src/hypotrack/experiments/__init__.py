"""Experiment drivers: run the library's trackers over the papers' scenarios and summarise them.

One package per experiment, mirroring ``workflows/rules/<experiment>.smk``; inside each, one module
per role on the data's way — ``run`` (scenario and Monte Carlo), ``oracle`` (independent
references), ``evaluation``, ``figures``, ``claims`` or ``summary`` (tables, ledger rows) — only
those the experiment has. The pipeline's scripts only read inputs, call these and write outputs.

Packages
--------
ssa               document 000 Sec. IV–V: R-FISST on the 50-object birth scenario (rules ssa, ssa50) and
                  R-FISST vs HOMHT on the 15-object scenario (ssa15).
ssa_seeds         the ssa50 / ssa15 verdicts over scenario seeds and over chain seeds of the report's realisation.
generation_time   document 000 Fig. 15 and the engine's throughput (generation_time, perf_hypotheses).
samplers          the chain vs Gibbs vs Murty on identical association problems.
belief_space      document 001's numeric claims against the engine and an independent density oracle.
glmb_benchmark    the GLMB papers' benchmark: δ-GLMB, R-FISST, HOMHT, Stone Soup's GM-PHD.
cardinality       document 003 §4: cardinality tracking.
swaps             document 003 §5: track swaps of GNNF, MHT and ECMHT.
closely_spaced    document 003 §6, Table 6.1: the four filters on two closely spaced targets.
sht               lecture notes 004: GNN and JPDA.
perf_sht          GNN / JPDA timing against Stone Soup.
perf_validation   the cost of input validation.
ssa_catalogue     SSA at catalogue scale: real objects seen by a ground radar, five trackers.

Shared modules
--------------
seeds             seed streams: one master seed, independent children per experiment and shard; shard sizes.
stepping          timing: wall/CPU clocks, best of repeats, steppers timed side by side in lock-step.

An experiment package imports another only through the shared modules, except the pairs documented
in ``tests/unit/test_package_layout.py`` (ssa_seeds and ssa_catalogue's single-event study use the
ssa package, which hosts ssa50 and ssa15).

(The Stone Soup adapter's benchmark, rule ``perf_interop``, lives with the adapter in
:mod:`hypotrack.interop.benchmark`; the ledger and report in :mod:`hypotrack.reporting`.)
"""
