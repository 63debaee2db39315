"""Seed 000 Fig. 15: hypothesis-generation time, and the engine's throughput (rules ``generation_time``, ``perf_hypotheses``).

Modules
-------
run         time per method and problem size; throughput and memory benchmarks
difficulty  the difficulty sweep: whether each method generates the true association
figures     Fig. 15, the difficulty grid and the throughput figure
claims      the Fig. 15 ledger rows (and its timing rows apart), the throughput and memory rows
"""
