"""Lecture notes 004: the worked example and GNN vs JPDA on crossing targets (rule ``sht``).

Modules
-------
run  the lecture's example, crossing-target and sweep Monte Carlo shards, ledger rows
"""
