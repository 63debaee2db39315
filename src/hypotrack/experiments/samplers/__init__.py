"""R-FISST's chain vs the GLMB Gibbs sampler vs Murty on identical problems (rule ``samplers``).

Modules
-------
run       the sweep over budgets and difficulties on synthetic problems
recorded  the samplers on association problems recorded from the GLMB benchmark's scans
summary   mass captured per budget and wall time: figure, ledger rows, macros
"""
