# Overhead of the Stone Soup adapter (hypotrack.interop.stonesoup) over hypotrack's own API, on one
# Stone Soup scenario, per algorithm (target: < 20 % of the tracker's own time). A measurement, not
# a test; the table is a timing table.
PI_DIR = f"{RESULTS}/perf"


rule perf_interop_benchmark:
    output:
        table=report_table(f"{PI_DIR}/stonesoup_adapter_timing.csv", "perf_interop", "stonesoup_adapter_timing"),
        pdf=f"{PI_DIR}/stonesoup_adapter_overhead.pdf",
        png=report_figure(f"{PI_DIR}/stonesoup_adapter_overhead.png", "perf_interop", "stonesoup_adapter_overhead"),
    params:
        cfg=config["perf_interop"],
    threads: 2  # timings want the machine to themselves
    script:
        "../scripts/perf_interop_benchmark.py"


PI_TARGETS = [*rules.perf_interop_benchmark.output]


rule perf_interop:
    input:
        PI_TARGETS,


ALL_TARGETS.extend(PI_TARGETS)
