"""ssa_catalogue fusion: one tracker on the radar alone and on the radar and the fence (same seeds), its two
scorecard rows with the runs' CPU seconds."""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.fused import SENSOR_SETS, build_fused, run_fused
from hypotrack.experiments.ssa_catalogue.run import check_tuning
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)
name = snakemake.wildcards.tracker  # noqa: F821
fusion = cfg["fusion"]
check_tuning(cfg)
cfg = {**cfg, "n_scans": fusion.get("n_scans") or cfg["n_scans"]}
n = int(fusion["n_objects"])
scenario, fused = build_fused(cfg, n, seed)
rows = []
for sensors in SENSOR_SETS:
    rows.append(run_fused(name, cfg, n, seed, scenario, fused, sensors))
    print(f"{name} N = {n}, {sensors}: {rows[-1]['cpu_s']:.1f} CPU s")
write_table(pd.DataFrame(rows), snakemake.output.cards)  # noqa: F821
