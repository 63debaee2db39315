"""GLMB benchmark, one Monte Carlo shard: per-scan metrics of every named tracker (with run times)."""
from hypotrack.experiments.glmb_benchmark.run import benchmark_shard
from hypotrack.experiments.seeds import experiment_seeds, shard_runs
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
shard = int(snakemake.wildcards.shard)  # noqa: F821
n_runs = shard_runs(cfg["n_runs"], cfg["n_shards"], shard)
first_run = sum(shard_runs(cfg["n_runs"], cfg["n_shards"], s) for s in range(shard))
seed = experiment_seeds(snakemake.params.seed, "glmb_benchmark", cfg["n_shards"])[shard]  # noqa: F821
print(f"glmb_benchmark shard {shard}/{cfg['n_shards']}: {n_runs} runs x {cfg['n_scans']} scans", flush=True)
write_table(benchmark_shard(cfg, seed, first_run, n_runs), snakemake.output.per_scan)  # noqa: F821
