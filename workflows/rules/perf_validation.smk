# Cost of input validation: the public (checked) Gaussian functions against their unchecked inner
# forms, and the share of each tracker's per-scan time spent in hypotrack._validation's checks
# (target: at most 5 %). A measurement, not a test; the tables are timing tables.
PV_DIR = f"{RESULTS}/perf"


rule perf_validation_benchmark:
    output:
        kernels=report_table(f"{PV_DIR}/validation_kernels_timing.csv", "perf_validation", "validation_kernels_timing"),
        trackers=report_table(f"{PV_DIR}/validation_trackers_timing.csv", "perf_validation",
                              "validation_trackers_timing"),
        pdf=f"{PV_DIR}/validation_cost.pdf",
        png=report_figure(f"{PV_DIR}/validation_cost.png", "perf_validation", "validation_cost"),
    params:
        cfg=config["perf_validation"],
    threads: 2  # timings want the machine to themselves
    script:
        "../scripts/perf_validation_benchmark.py"


PV_TARGETS = [*rules.perf_validation_benchmark.output]


rule perf_validation:
    input:
        PV_TARGETS,


ALL_TARGETS.extend(PV_TARGETS)
