"""GLMB benchmark: record the association problems of one seeded run (input of the sampler head-to-head)."""
from hypotrack.reporting.joblog import prefix_output
from hypotrack.experiments.glmb_benchmark.recorded import record_problems, save_problems
from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
rec = snakemake.params.recorded  # noqa: F821
seed = experiment_seeds(snakemake.params.seed, "glmb_benchmark_record", 1)[0]  # noqa: F821
problems, table = record_problems(cfg, cfg["trackers"]["glmb"], seed, int(rec["n_problems"]))
print(f"glmb_benchmark_record: {len(problems)} problems from scans {list(table.scan)}", flush=True)
save_problems(problems, snakemake.output.problems)  # noqa: F821
write_table(table, snakemake.output.table)  # noqa: F821
