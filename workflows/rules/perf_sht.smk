# Speed-up targets, measured (not asserted in tests): hypotrack's GNN and JPDA per-scan
# time against Stone Soup's GNNWith2DAssignment, JPDAwithEHM2 and brute-force JPDA on the same
# closely spaced formations in one run (lock-step, alternating order), with the speed-up ratios,
# the marginals/associations compared, and the largest formation each handles within 1 s/scan.
# Stone Soup is a benchmark-only dependency: without it the rule times hypotrack alone.
PS_DIR = f"{RESULTS}/perf"


rule perf_sht_benchmark:
    output:
        timings=f"{PS_DIR}/sht_timings.csv",
        speedups=report_table(f"{PS_DIR}/sht_speedups.csv", "perf_sht", "sht_speedups"),
        largest_runs=f"{PS_DIR}/sht_largest_runs.csv",
        largest=f"{PS_DIR}/sht_largest_cluster.csv",
        pdf=f"{PS_DIR}/sht_timings.pdf",
        png=report_figure(f"{PS_DIR}/sht_timings.png", "perf_sht", "sht_timings"),
    params:
        cfg=config["perf_sht"],
    threads: 2  # timings want the machine to themselves
    script:
        "../scripts/perf_sht_benchmark.py"


rule perf_sht_claims:
    input:
        speedups=rules.perf_sht_benchmark.output.speedups,
        largest=rules.perf_sht_benchmark.output.largest,
        timings=rules.perf_sht_benchmark.output.timings,
    output:
        claims=f"{PS_DIR}/sht_timing_claims.csv",  # speed-ups: timing, not byte-reproducible
    script:
        "../scripts/perf_claims.py"


PS_TARGETS = [*rules.perf_sht_benchmark.output, *rules.perf_sht_claims.output]


rule perf_sht:
    input:
        PS_TARGETS,


ALL_TARGETS.extend(PS_TARGETS)
