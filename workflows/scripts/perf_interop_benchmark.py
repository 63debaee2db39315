"""Stone Soup adapter overhead over hypotrack's own API (thin: hypotrack.interop.benchmark)."""

from hypotrack.reporting.joblog import prefix_output
from hypotrack.interop.benchmark import adapter_overhead, plot_overhead

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg
table = adapter_overhead(cfg["algorithms"], n_targets=cfg["n_targets"], n_scans=cfg["n_scans"],
                         clutter_rate=cfg["clutter_rate"], repeats=cfg["repeats"], seed=cfg["seed"])
table.to_csv(snakemake.output.table, index=False, float_format="%.6g")
for row in table.itertuples():
    print(f"{row.algorithm}: {row.own_api_ms_per_scan:.3f} ms/scan own API, {row.adapter_ms_per_scan:.3f} through "
          f"the adapter ({100 * row.overhead:+.0f} %)", flush=True)
plot_overhead(table, snakemake.output.pdf, snakemake.output.png, target=cfg["target_overhead"])
