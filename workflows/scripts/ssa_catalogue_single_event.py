"""ssa_catalogue: document 000's single-event population through the factored engine, on the ssa50 scans
(R-FISST unfactored, factored, and reseeded as the noise floor): per-scan table, summary, ledger rows, macros."""

import pandas as pd

from hypotrack.experiments.ssa import TrackerSettings, scenario_from_files
from hypotrack.experiments.ssa_catalogue.single_event import (
    SingleEventSettings,
    pair_summary,
    single_event_claims,
    single_event_comparison,
    single_event_macros,
)
from hypotrack.reporting.joblog import prefix_output, progress_log
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
config, inp, out = snakemake.config, snakemake.input, snakemake.output
settings = SingleEventSettings.from_config(config["ssa_catalogue"]["single_event"])
scenario = scenario_from_files(config, "ssa50", inp.truth, inp.scans, inp.prior)
with progress_log(snakemake.log[0]) as progress:
    per_scan, cpu = single_event_comparison(scenario, settings, config["ssa50"], config["seed"], progress=progress)
    summary = pair_summary(per_scan)
    write_table(per_scan, out.per_scan)
    write_table(summary, out.summary)
    write_table(pd.DataFrame({"run": list(cpu), "cpu_seconds": list(cpu.values())}), out.timing)
    h_inf = TrackerSettings.from_config(config["ssa50"], settings.tracker).max_hypotheses
    write_claims(single_event_claims(summary, per_scan, settings, h_inf), out.claims)
    write_macros("ssa_catalogue", single_event_macros(summary, per_scan, settings), out.macros)
    progress(summary.to_string(index=False))
    progress("CPU seconds: " + ", ".join(f"{k} {v:.1f}" for k, v in cpu.items()))
