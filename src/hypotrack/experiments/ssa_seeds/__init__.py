"""The ssa50 and ssa15 verdicts over scenario seeds (rule ``ssa_seeds``).

Modules
-------
run      one scenario seed per shard; the over-seed table
figures  every seed's value and the quartiles per case and tracker
claims   each SSA verdict over seeds, with the blind tracker as its control
"""
