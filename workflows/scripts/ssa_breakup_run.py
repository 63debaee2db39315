"""ssa_breakup: one tracker's scorecard on every scenario and seed (CPU seconds included: a timing file), and the
sweep of its ambiguity output's p_min (empty for GNN/JPDA)."""
from hypotrack.experiments.ssa_breakup.jobs import score_tracker_outputs
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, catalogue = snakemake.params.cfg, snakemake.params.catalogue  # noqa: F821 (injected by Snakemake)
name = snakemake.wildcards.tracker  # noqa: F821
cards, sweep = score_tracker_outputs(name, cfg, catalogue)
for r in cards.itertuples(index=False):
    print(f"{name} {r.scenario} seed {r.seed}: {r.cross_tags_per_1e4:.1f} cross-tags per 1e4 returns, {r.cpu_s:.1f} CPU s")
write_table(cards, snakemake.output.cards)  # noqa: F821
write_table(sweep, snakemake.output.sweep)  # noqa: F821
