"""Cost of input validation (thin: hypotrack.experiments.perf_validation.run)."""

from hypotrack.reporting.joblog import prefix_output
from hypotrack.experiments.perf_validation.run import kernel_overhead, plot_validation_cost, tracker_validation_share

prefix_output(snakemake)  # every line this job prints names the job

cfg = snakemake.params.cfg
kernels = kernel_overhead(cfg["sizes"], n_returns=cfg["n_returns"], repeats=cfg["repeats"], seed=cfg["seed"])
kernels.to_csv(snakemake.output.kernels, index=False, float_format="%.6g")
trackers = tracker_validation_share(cfg["algorithms"], n_targets=cfg["n_targets"], n_scans=cfg["n_scans"],
                                    clutter_rate=cfg["clutter_rate"], repeats=cfg["repeats"], seed=cfg["seed"])
trackers.to_csv(snakemake.output.trackers, index=False, float_format="%.6g")
for row in trackers.itertuples():
    print(f"{row.algorithm}: {row.step_ms_per_scan:.3f} ms/scan, {row.validation_ms_per_scan:.4f} ms in checks "
          f"({100 * row.validation_share:.1f} %, target <= {100 * cfg['target_share']:.0f} %)", flush=True)
plot_validation_cost(kernels, trackers, snakemake.output.pdf, snakemake.output.png, target=cfg["target_share"])
