"""Seed 003 §4, Fig. 4.2: cardinality tracking Monte Carlo (rule ``cardinality``).

Modules
-------
run      one realisation, shards, the Tetris extraction against the exact count DP
figures  Fig. 4.2: truth and every method's number of targets over one realisation
claims   the ledger rows of document 003 §4
"""
