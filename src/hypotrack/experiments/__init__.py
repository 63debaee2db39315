"""Experiment drivers: run the library's trackers over the papers' scenarios and summarise them.

Each driver turns a config section (and saved scenario tables) into tables, figures and
reproduction claims; the pipeline's scripts only read and write files. One module per experiment:

Modules
-------
ssa                       seed 000 Sec. IV–V (a package, one module per step): R-FISST on the
                          50-object birth scenario (Figs 6, 8–11) and R-FISST vs HOMHT on the 15-object scenario (Figs 12–14).
generation_time           seed 000 Fig. 15: hypothesis-generation time; throughput benchmarks.
generation_time_figures   figures of the hypothesis-engine experiments.
belief_space              seed 001's numeric claims against the hypothesis engine.
belief_space_claims       the belief_space checks table and ledger rows, each with its evidence.
belief_space_oracle       the engine's one-scan posterior against the independent density oracle.
fisst_oracle              brute-force FISST / Reid densities of one scan (numpy and scipy only).
cardinality               seed 003 §4, Fig. 4.2: cardinality tracking Monte Carlo.
ecmht                     seed 003 §5: the swap experiment (Figs 5.1–5.3); Monte Carlo shard sizes.
closely_spaced            seed 003 Table 6.1, Figs 6.1–6.2: Monte Carlo of the four filters.
closely_spaced_oracle     the ideal filter's MOSPA in closed form (Riccati moments), every convention.
closely_spaced_claims     Table 6.1 ledger rows: Monte Carlo verdicts, closed form, published ideal.
closely_spaced_figures    MOSPA over time and Figs 6.1–6.2.
sht                       lecture notes 004: worked example, GNN vs JPDA on crossing targets.
perf_sht                  per-scan timing of GNN and JPDA against a peer implementation.
glmb_benchmark            the GLMB papers' linear-Gaussian benchmark: δ-GLMB (Gibbs), R-FISST, HOMHT.
glmb_benchmark_report     its side-by-side table, curves over time, figure and ledger rows.
samplers                  R-FISST's chain vs the GLMB Gibbs sampler vs Murty on identical problems.
samplers_report           its figure (mass missed vs budget and wall time) and ledger rows.
seeds                     seed streams: one master seed, independent children per experiment.
"""
