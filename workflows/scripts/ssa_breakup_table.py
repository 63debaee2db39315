"""ssa_breakup: scorecard per tracker and seed, mean ± s.e., cross-tag ratios, figure, ledger rows and macros."""
import pandas as pd

from hypotrack.experiments.ssa_breakup.figures import plot_breakup
from hypotrack.experiments.ssa_breakup.jobs import smallest_gate_km
from hypotrack.experiments.ssa_breakup.record import record_claims, record_macros
from hypotrack.experiments.ssa_breakup.summary import (EXPERIMENT, TIMING_COLUMNS, ambiguity_sweep, breakup_claims,
                                                        breakup_macros, breakup_ratios, density_table,
                                                        merged_sweeps, scorecard_summary)
from hypotrack.experiments.ssa_breakup.tuning import evaluated_cards
from hypotrack.reporting.joblog import prefix_output
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, out = snakemake.params.cfg, snakemake.output  # noqa: F821 (injected by Snakemake)
cards = pd.concat([pd.read_csv(p) for p in snakemake.input.cards], ignore_index=True)  # noqa: F821
# the ambiguity outputs at the p_min chosen on the tuning seeds (ambiguity.tuning), or at ambiguity.p_min without one
tuning = pd.read_csv(snakemake.input.tuning[0]) if snakemake.input.tuning else None  # noqa: F821
cards, p_used = evaluated_cards(cards, cfg, tuning)
record = pd.read_csv(snakemake.input.record[0]) if snakemake.input.record else pd.DataFrame()  # noqa: F821
write_table(cards.drop(columns=list(TIMING_COLUMNS)), out.scorecard)
summary, timing = scorecard_summary(cards)
write_table(summary, out.summary)
write_table(timing, out.timing)
# the operator's cross-tags (the goal's), then the standard crediting's identity switches
ratios = breakup_ratios(cards, cfg["trackers_run"], cfg["reference_tracker"], cfg["ratio_goal"])
write_table(ratios, out.ratios)
sweep = merged_sweeps([pd.read_csv(p) for p in snakemake.input.sweeps])  # noqa: F821
write_table(ambiguity_sweep(sweep, cards, cfg["reference_tracker"], cfg["ratio_goal"]), out.ambiguity)
density = density_table(pd.read_csv(snakemake.input.density).to_dict("records"))  # noqa: F821
dist = pd.read_csv(snakemake.input.distances)  # noqa: F821
plot_breakup({s: g["nn_km"].to_numpy() for s, g in dist.groupby("scenario", sort=False)}, smallest_gate_km(cfg),
             summary, out.fig_pdf, out.fig_png, ratios)
write_claims(breakup_claims(summary, ratios, density, cfg["reference_tracker"])
             + record_claims(record, cfg["reference_tracker"]), out.claims)
macros = breakup_macros(summary, ratios, density)
if p_used is not None:
    macros["amb_pmin"] = p_used
write_macros(EXPERIMENT, {**macros, **record_macros(record)}, out.macros)
