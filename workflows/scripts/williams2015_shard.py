"""Williams-2015, one Monte Carlo shard: per-scan GOSPA (with run times) and per-run trajectory GOSPA of every tracker."""
from hypotrack.experiments.seeds import shard_runs
from hypotrack.experiments.williams2015.run import run_shard
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
shard = int(snakemake.wildcards.shard)  # noqa: F821
n_runs = shard_runs(cfg["n_runs"], cfg["n_shards"], shard)
first_run = sum(shard_runs(cfg["n_runs"], cfg["n_shards"], s) for s in range(shard))
print(f"williams2015 shard {shard}/{cfg['n_shards']}: runs {first_run}..{first_run + n_runs - 1}", flush=True)
per_scan, per_run = run_shard(cfg, snakemake.params.seed, first_run, n_runs)  # noqa: F821
write_table(per_scan, snakemake.output.per_scan)  # noqa: F821
write_table(per_run, snakemake.output.per_run)  # noqa: F821
