"""Williams-2015: the PMBM paper's own filter under GNU Octave on the first runs' scans (or its committed record)."""
from hypotrack.experiments.williams2015.reference import reference_estimates
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
est, times, source = reference_estimates(cfg, snakemake.params.seed, snakemake.input.driver)  # noqa: F821
print(f"williams2015 reference: {times.run.nunique()} runs from the {source}", flush=True)
write_table(est, snakemake.output.estimates)  # noqa: F821
write_table(times, snakemake.output.timing)  # noqa: F821
