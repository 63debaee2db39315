"""hypotrack: multi-target tracking trackers and the experiments of the papers they come from.

Subpackages
-----------
gaussian      Kalman/EKF predict/update and Gaussian log-likelihoods, batched over tracks.
models        motion, sensor and population (birth/death) models.
scenarios     deterministic generators of ground truth and scans.
association   association matrices, gating, clustering, enumeration, k-best, MCMC.
hypotheses    the hypothesis-level filter: H-FISST, R-FISST and HOMHT as one engine.
trackers      GNN, JPDA/PDAF, track initiation, ECMHT and cardinality tracking.
metrics       OSPA and GOSPA.
"""

__version__ = "0.1.0"
