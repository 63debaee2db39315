"""The GLMB papers' linear-Gaussian benchmark: δ-GLMB (Gibbs), R-FISST, HOMHT, GM-PHD (rule ``glmb_benchmark``).

Modules
-------
run       scenario, trackers and Monte Carlo shards
gmphd     Stone Soup's GM-PHD on the same scans (the peer baseline)
recorded  the δ-GLMB's association problems of one run, saved for the sampler head-to-head
summary   the side-by-side table, curves over time, figure, ledger rows and macros
"""
