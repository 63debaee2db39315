# Performance targets of the hypothesis engine, measured (not asserted in tests):
# MCMC proposals per second at M = m = 28, exhaustive children enumerated and weighted per
# second, and the memory bound of exhaustive generation (a budget error, never an OOM).
PH_DIR = f"{RESULTS}/perf"


rule perf_hypotheses_benchmark:
    output:
        table=report_table(f"{PH_DIR}/hypotheses_throughput.csv", "perf_hypotheses", "hypotheses_throughput_table"),
        pdf=f"{PH_DIR}/hypotheses_throughput.pdf",
        png=report_figure(f"{PH_DIR}/hypotheses_throughput.png", "perf_hypotheses", "hypotheses_throughput"),
    params:
        cfg=config["perf_hypotheses"],
    threads: 2  # timings want the machine to themselves
    script:
        "../scripts/perf_hypotheses_benchmark.py"


rule perf_hypotheses_claims:
    input:
        throughput=rules.perf_hypotheses_benchmark.output.table,
    output:
        claims=f"{PH_DIR}/hypotheses_timing_claims.csv",  # throughput: timing, not byte-reproducible
    script:
        "../scripts/perf_claims.py"


PH_TARGETS = [*rules.perf_hypotheses_benchmark.output, *rules.perf_hypotheses_claims.output]


rule perf_hypotheses:
    input:
        PH_TARGETS,


ALL_TARGETS.extend(PH_TARGETS)
