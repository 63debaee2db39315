"""SSA Monte Carlo over seeds: per-seed and per-chain tables, distributions over seeds, ledger rows and figure."""

import matplotlib

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from hypotrack.reporting.joblog import claims_line, prefix_output  # noqa: E402
from hypotrack.experiments.ssa_seeds.chains import CHAIN_COLUMNS  # noqa: E402
from hypotrack.experiments.ssa_seeds.claims import chain_seed_claims, ssa_seeds_claims  # noqa: E402
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
per_chain = (pd.concat([pd.read_csv(p) for p in inp.chain_rows], ignore_index=True) if inp.chain_rows
             else pd.DataFrame(columns=CHAIN_COLUMNS))
write_table(per_chain, out.per_chain)
write_table(distribution_table(per_chain), out.chain_summary)
write_table(pd.concat([pd.read_csv(p) for p in inp.chain_timing], ignore_index=True) if inp.chain_timing
            else pd.DataFrame(columns=["case", "chain_index", "tracker", "seconds", "cpu_seconds"]), out.chain_timing)
fig = plot_distributions(per_seed, title="SSA verdicts over seeds (document 000 Sec. IV-A, V-A)",
                         per_chain=per_chain if len(per_chain) else None)
figure_style.save(fig, out.fig_pdf, out.fig_png)
claims = ssa_seeds_claims(per_seed) + (chain_seed_claims(per_chain) if len(per_chain) else [])
print(claims_line(write_claims(claims, out.claims), out.claims), flush=True)
