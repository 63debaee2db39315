"""Seed 001's numeric claims against the hypothesis engine (rule ``belief_space``).

Modules
-------
run           the claims from the formulas and from the engine's own weights (Eq. 9/20 ratio, Eq. 43 bound)
figures       the Eq. 39 ratio, the Eq. 43 bound and the Sec. V-A equivalence figures
oracle        the engine's one-scan posterior against the independent density oracle
fisst_oracle  brute-force FISST / Reid densities of one scan (numpy and scipy only)
claims        the checks table and ledger rows, each with its evidence
"""
