"""ssa_catalogue: the same scans through one factored tracker with 1 and with several workers (timing table)."""
from hypotrack.experiments.ssa_catalogue.run import parallel_timing
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)
p = cfg["parallel"]
table = parallel_timing(p["tracker"], cfg, p["n_objects"], seed, p["workers"], p["pools"])
for _, r in table.iterrows():
    print(f"{r.pool} x{r.workers}: wall {r.wall_s_per_scan:.4f} s/scan, speed-up {r.speedup_wall:.2f}, "
          f"identical {r.identical}")
write_table(table, snakemake.output.timing)  # noqa: F821
