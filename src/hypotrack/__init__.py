"""hypotrack: multi-target tracking trackers and the experiments of the papers they come from.

Subpackages, from the bottom up
-------------------------------
gaussian      Kalman/EKF predict/update and Gaussian log-likelihoods, batched over tracks.
models        motion, sensor and population (birth/death) models.
scenarios     deterministic generators of ground truth and scans (no drawing).
association   association matrices, gating, clustering, enumeration, k-best; ``samplers``: the
              association events, visited set, R-FISST's chain and the Gibbs sweeps.
protocol      the one tracker surface: initialise, step(Z, time), estimates, posterior.
hypotheses    the hypothesis-level filter: H-FISST, R-FISST, HOMHT and δ-GLMB as one engine, its
              state apart from its configuration; ``factored``: the same engine on independent groups.
trackers      GNN, JPDA/PDAF, track initiation, ECMHT and cardinality tracking.
registry      tracker specifications (kind plus options, one schema of defaults) built on a tracking
              problem: how every experiment and the Stone Soup adapter make their trackers.
metrics       OSPA and GOSPA.
reporting     the ledger's claims and rules, its files, macros and renderers; README and paper inputs.
experiments   one package per experiment of the pipeline (run, figures, claims apart).
interop       Stone Soup: hypotrack's trackers as Stone Soup trackers, and Stone Soup as a peer.
"""

__version__ = "0.1.0"
