"""The ssa50 and ssa15 verdicts over scenario seeds and over chain seeds (rule ``ssa_seeds``).

Modules
-------
run      one scenario seed per shard; the over-seed table
chains   one chain seed per shard: the report's realisation, a new MCMC stream
figures  every seed's value and the quartiles per case and tracker
claims   each SSA verdict over scenario seeds and over chain seeds, with the blind tracker as its control
"""
