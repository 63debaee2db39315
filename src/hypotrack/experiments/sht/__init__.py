"""Lecture notes 004: the worked example and GNN vs JPDA on crossing targets (rule ``sht``).

Modules
-------
run      the lecture's example, crossing-target and sweep Monte Carlo shards
figures  coalescence on crossing targets and the clutter sweep
claims   the ledger rows and the worked example's macros
"""
