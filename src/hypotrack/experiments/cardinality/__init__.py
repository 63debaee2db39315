"""Seed 003 §4, Fig. 4.2: cardinality tracking Monte Carlo (rule ``cardinality``).

Modules
-------
run  one realisation, shards, the Tetris extraction against the exact count DP, ledger rows
"""
