"""One chain seed of the SSA Monte Carlo: the case's trackers on the report's realisation, a new MCMC stream each."""

from hypotrack.experiments.ssa import scenario_from_files
from hypotrack.experiments.ssa_seeds.chains import run_chain_seed
from hypotrack.reporting.joblog import prefix_output, progress_log
from hypotrack.scenarios.tables import write_table

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
case, inp = snakemake.wildcards.case, snakemake.input
with progress_log(snakemake.log[0]) as progress:
    # the tables the report's single runs read: the chain seeds vary nothing else
    scenario = scenario_from_files(snakemake.config, case, inp.truth, inp.scans, inp.prior)
    rows, timing = run_chain_seed(snakemake.config, case, int(snakemake.wildcards.chain), progress=progress,
                                  scenario=scenario)
    write_table(rows, snakemake.output.rows)
    write_table(timing, snakemake.output.timing)
    progress(timing.to_string(index=False))
