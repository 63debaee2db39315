"""Engine vs the independent oracle of the seeds' densities on small random scans (thin)."""

from hypotrack.experiments.belief_space.oracle import oracle_table
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg  # noqa: F821
print(f"belief_space oracle: {cfg['n_scenes']} scans, FISST and HOMHT against the brute-force densities", flush=True)
write_table(oracle_table(cfg, snakemake.params.seed), snakemake.output.table)  # noqa: F821
