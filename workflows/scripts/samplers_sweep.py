"""Sampler head-to-head: run every sampler on the same problems; tables, figure, ledger rows."""
from hypotrack.experiments.glmb_benchmark.recorded import load_problems
from hypotrack.experiments.samplers.run import samplers_sweep, summarise
from hypotrack.experiments.samplers.summary import compute_claims, plot_mass, sampler_claims, sampler_macros, time_to_mass
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
out = snakemake.output  # noqa: F821
recorded = load_problems(snakemake.input.recorded)  # noqa: F821
raw = samplers_sweep(cfg, experiment_seeds(snakemake.params.seed, "samplers", 1)[0], recorded)  # noqa: F821
det, timing = summarise(raw)
write_table(raw, out.raw)
write_table(det, out.summary)
write_table(timing, out.timing)
plot_mass(det, timing, out.fig_pdf, out.fig_png)
write_claims(sampler_claims(det, timing), out.claims)
values, times = sampler_macros(det, timing)
write_macros("samplers", values, out.macros)
timed_claims, per_compute = compute_claims(det, timing)
write_table(time_to_mass(det, timing), out.time_to_mass)
write_claims(timed_claims, out.compute_claims)
write_macros("samplers", {**times, **per_compute}, out.timing_macros)
