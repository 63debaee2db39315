"""ssa50 sensitivity grid: P(N = 50) at the end per (λ, p_D) with the Monte Carlo verdict, ledger row, macros, figure."""

import matplotlib

matplotlib.use("Agg")
from hypotrack.reporting import figure_style  # noqa: E402
import pandas as pd  # noqa: E402

from hypotrack.experiments.ssa import sensitivity as sv  # noqa: E402
from hypotrack.reporting.joblog import claims_line, prefix_output  # noqa: E402
from hypotrack.reporting.ledger import write_claims, write_macros  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
prefix_output(snakemake)  # every line this job prints names the job
inp, out, own = snakemake.input, snakemake.output, snakemake.params.section
ssa = snakemake.params.ssa
runs = pd.concat([pd.read_csv(p) for p in inp.rows], ignore_index=True)
timing = pd.concat([pd.read_csv(p) for p in inp.timing], ignore_index=True)
table = sv.sensitivity_table(runs, tracker=own["tracker"], tolerance=own["tolerance"])
write_table(runs, out.runs)
write_table(table, out.table)
write_table(timing, out.timing)
print(table.to_string(index=False), flush=True)
claims, macros = sv.sensitivity_claims(table, tolerance=own["tolerance"],
                                       configured=(float(ssa["clutter_rate"]), float(ssa["p_D"])))
write_macros("ssa_sensitivity", macros, out.macros)
fig = sv.plot_sensitivity(table, tolerance=own["tolerance"])
figure_style.save(fig, out.fig_pdf, out.fig_png, width=1.0)
print(claims_line(write_claims(claims, out.claims), out.claims), flush=True)
