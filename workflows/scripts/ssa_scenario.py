"""Generate one SSA scenario (snakemake.wildcards.case) and save its tables."""

import time

from hypotrack.scenarios.ssa import prior_table, scenario_from_config
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
case = snakemake.wildcards.case
start = time.perf_counter()
scenario = scenario_from_config(snakemake.config, case)
write_table(scenario.truth, snakemake.output.truth)
write_table(scenario.scans, snakemake.output.scans)
write_table(prior_table(scenario), snakemake.output.prior)
p = scenario.params
n_clutter = int((scenario.scans["origin"] == -1).sum())
births = scenario.birth_ids.tolist()
first = scenario.first_in_view_scan[scenario.birth_ids].tolist()
summary = (
    f"{case}: {p.n_objects} objects ({p.n_known} known), {p.n_scans} scans, {len(scenario.scans)} returns "
    f"({n_clutter} clutter); births {births} first in view at scans {first}; "
    f"{time.perf_counter() - start:.2f} s"
)
print(summary)
with open(snakemake.log[0], "w") as log:
    print(summary, file=log)
