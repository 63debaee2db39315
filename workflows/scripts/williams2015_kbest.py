"""Williams-2015 companion: Murty's k best, murty_k_best against nrl-tracker's murty on the same costs (timed)."""
import numpy as np

from hypotrack.experiments.seeds import experiment_seeds
from hypotrack.experiments.williams2015.kbest import kbest_benchmark
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

kb = snakemake.params.cfg["kbest"]  # noqa: F821 (injected by Snakemake)
rng = np.random.default_rng(experiment_seeds(snakemake.params.seed, "williams2015_kbest", 1)[0])  # noqa: F821
table = kbest_benchmark(kb["n"], kb["k"], kb["n_problems"], kb["repeats"], rng, kb["target_ms"])
print(table.to_string(), flush=True)
write_table(table, snakemake.output.timing)  # noqa: F821
