"""ssa_breakup: one tracker on the ambiguity output's tuning seeds (the section's other settings), its scorecard and
p_min sweep, as the evaluated runs' (experiments/ssa_breakup/tuning.py)."""
from hypotrack.experiments.ssa_breakup.jobs import score_tracker_outputs
from hypotrack.experiments.ssa_breakup.tuning import tuning_section
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, catalogue = snakemake.params.cfg, snakemake.params.catalogue  # noqa: F821 (injected by Snakemake)
name = snakemake.wildcards.tracker  # noqa: F821
cards, sweep = score_tracker_outputs(name, tuning_section(cfg), catalogue)
for r in cards.itertuples(index=False):
    print(f"{name} tuning seed {r.seed}: {r.cross_tags_per_1e4:.1f} cross-tags per 1e4 returns, {r.cpu_s:.1f} CPU s")
write_table(cards, snakemake.output.cards)  # noqa: F821
write_table(sweep, snakemake.output.sweep)  # noqa: F821
