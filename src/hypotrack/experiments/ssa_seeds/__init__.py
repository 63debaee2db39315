"""The ssa50 and ssa15 verdicts over scenario seeds (rule ``ssa_seeds``).

Modules
-------
run  one scenario seed per shard; the over-seed table and its ledger rows
"""
