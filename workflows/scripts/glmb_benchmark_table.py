"""GLMB benchmark: side-by-side table, curves over time, figure and ledger rows from the shards."""
import pandas as pd

from hypotrack.experiments.glmb_benchmark.run import implementation_labels, legend_labels
from hypotrack.experiments.glmb_benchmark.summary import (
    benchmark_claims,
    benchmark_macros,
    curves,
    follow_claims,
    follow_macros,
    follow_score,
    plot_benchmark,
    summary_table,
)
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.tables import write_table
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
out = snakemake.output  # noqa: F821
per_scan = pd.concat([pd.read_csv(p) for p in snakemake.input.per_scan], ignore_index=True)  # noqa: F821
trackers = cfg["trackers"]
controls = [name for name, spec in trackers.items() if spec["kind"] == "blind"]
implementations = implementation_labels(trackers)
summary, timing = summary_table(per_scan, implementations)
write_table(summary, out.summary)
write_table(timing, out.timing)
curve = curves(per_scan)
write_table(curve, out.curves)
shown = curve[~curve.tracker.isin(controls)].copy()
shown.attrs["n_runs"] = per_scan.run.nunique()
plot_benchmark(shown, out.fig_pdf, out.fig_png, legend_labels(trackers))
claims = benchmark_claims(summary, cfg["reference_tracker"], controls)
follow = cfg["follow_check"]
peers = [name for name, spec in trackers.items() if spec["kind"] == "gmphd"]
claims += follow_claims(per_scan, follow["trackers"], follow["control"], follow["lag"], follow["tolerance"],
                        peers[0] if peers else None, truth_rows=cfg["truth"], birth_std=cfg["birth_std"])
write_claims(claims, out.claims)
values, times = benchmark_macros(summary, timing)
values.update(FollowLag=follow["lag"], FollowTolerance=f"{follow['tolerance']:g}",
              FollowControlOutside=f"{follow_score(per_scan, follow['control'], follow['lag'])[0]:.2f}")
values.update(follow_macros(per_scan, follow["trackers"], follow["lag"], cfg["truth"]))
write_macros("glmb_benchmark", values, out.macros)
write_macros("glmb_benchmark", times, out.timing_macros)
