"""SSA Monte Carlo over seeds: per-seed table, distribution over seeds, ledger rows and figure."""

import matplotlib

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from hypotrack.reporting.joblog import claims_line, prefix_output  # noqa: E402
from hypotrack.experiments.ssa_seeds.claims import ssa_seeds_claims  # noqa: E402
from hypotrack.experiments.ssa_seeds.figures import plot_distributions  # noqa: E402
from hypotrack.experiments.ssa_seeds.run import distribution_table  # noqa: E402
from hypotrack.reporting import figure_style  # noqa: E402
from hypotrack.reporting.ledger import write_claims  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
inp, out = snakemake.input, snakemake.output
per_seed = pd.concat([pd.read_csv(p) for p in inp.rows], ignore_index=True)
timing = pd.concat([pd.read_csv(p) for p in inp.timing], ignore_index=True)
write_table(per_seed, out.per_seed)
write_table(distribution_table(per_seed), out.summary)
write_table(timing, out.timing)
fig = plot_distributions(per_seed, title="SSA verdicts over scenario seeds (document 000 Sec. IV-A, V-A)")
figure_style.save(fig, out.fig_pdf, out.fig_png)
print(claims_line(write_claims(ssa_seeds_claims(per_seed), out.claims), out.claims), flush=True)
