"""ssa_catalogue: one tracker over every population size (one timed pass that also records the operator's
scorecard, then a short traced pass for memory)."""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.run import build_scenario, check_tuning, run_tracker
from hypotrack.experiments.ssa_catalogue.scorecard import run_with_scorecard
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)
name = snakemake.wildcards.tracker  # noqa: F821
out = snakemake.output  # noqa: F821
check_tuning(cfg)
per_scan, assign, memory, cards = [], [], [], []
for n in cfg["sizes"]:
    scenario = build_scenario(cfg, n, seed)
    ps, a, card = run_with_scorecard(name, cfg, n, seed, scenario)
    per_scan.append(ps)
    assign.append(a)
    cards.append(card)
    _, _, info = run_tracker(name, cfg, n, seed, scenario=scenario, memory=True)
    memory.append(dict(tracker=name, n_objects=n, peak_bytes=info["peak_bytes"]))
    print(f"{name} N = {n}: {ps.cpu_s.mean():.4f} CPU s per scan, {len(ps)} scans")
write_table(pd.concat(per_scan, ignore_index=True), out.per_scan)
write_table(pd.concat(assign, ignore_index=True), out.assign)
write_table(pd.DataFrame(memory), out.memory)
write_table(pd.DataFrame(cards), out.card)
