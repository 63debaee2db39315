# Seed 000 Sec. V-A, Figs 12-14: R-FISST (the paper's chain alone, and chain + this project's completion
# step) vs HOMHT (same EKF) on the 15-object SSA scenario, all objects known and starting in view. One sequential job per tracker (they run in parallel); the
# comparisons, figures and claims are drawn from their tables.
# Config section: ssa15 (workflows/config/schema/ssa15.schema.yaml); scenario: rule ssa_scenario.
SSA15_DIR = f"{RESULTS}/ssa15"
SSA15_TRACKERS = list(config["ssa15"]["trackers"])
SSA15_TABLES = ["summary", "cardinality", "map_estimates", "weights", "timing"]
for _pair in config["ssa15"]["comparisons"]:
    if not set(_pair) <= set(SSA15_TRACKERS):
        raise ValueError(f"ssa15.comparisons: {_pair} names a tracker not in ssa15.trackers {SSA15_TRACKERS}")


rule ssa15_run:
    wildcard_constraints:
        tracker="|".join(SSA15_TRACKERS),
    input:
        truth=f"{RESULTS}/ssa/ssa15_truth.csv",
        scans=f"{RESULTS}/ssa/ssa15_scans.csv",
        prior=f"{RESULTS}/ssa/ssa15_prior.csv",
    output:
        **{table: f"{SSA15_DIR}/{{tracker}}_{table}.csv" for table in SSA15_TABLES},
    log:
        f"{RESULTS}/logs/ssa15/{{tracker}}_run.log",
    params:
        # What the run reads (the script takes it from the config): a change reruns only this tracker.
        settings=lambda wc: {
            "master_seed": config["seed"],
            "tracker": config["ssa15"]["trackers"][wc.tracker],
            **{k: config["ssa15"][k] for k in ["max_hypotheses", "gate_probability", "snapshots"]},
            **({} if config["ssa15"]["trackers"][wc.tracker]["kind"] == "homht"
               else {"population": config["ssa15"]["population"]}),
        },
    script:
        "../scripts/ssa15_run.py"


SSA15_RUN = expand(f"{SSA15_DIR}/{{tracker}}_{{table}}.csv", tracker=SSA15_TRACKERS, table=SSA15_TABLES)


rule ssa15_figures:
    input:
        **{f"{tr}_map": f"{SSA15_DIR}/{tr}_map_estimates.csv" for tr in SSA15_TRACKERS},
        **{f"{tr}_summary": f"{SSA15_DIR}/{tr}_summary.csv" for tr in SSA15_TRACKERS},
        **{f"{tr}_timing": f"{SSA15_DIR}/{tr}_timing.csv" for tr in SSA15_TRACKERS},
        truth=f"{RESULTS}/ssa/ssa15_truth.csv",
        scans=f"{RESULTS}/ssa/ssa15_scans.csv",
        prior=f"{RESULTS}/ssa/ssa15_prior.csv",
    output:
        metrics=report_table(f"{SSA15_DIR}/metrics.csv", "ssa15", "metrics"),
        agreement=report_table(f"{SSA15_DIR}/agreement.csv", "ssa15", "agreement"),
        control_metrics=f"{SSA15_DIR}/blind_metrics.csv",  # the negative control's per-scan metrics
        snapshots=f"{SSA15_DIR}/estimate_snapshots.csv",
        completion=report_table(f"{SSA15_DIR}/completion.csv", "ssa15", "completion"),
        completion_timing=f"{SSA15_DIR}/completion_timing.csv",
        fig12_pdf=f"{SSA15_DIR}/fig_12_14_estimates.pdf",
        fig12_png=report_figure(f"{SSA15_DIR}/fig_12_14_estimates.png", "ssa15", "fig_12_14_estimates"),
        comparison_pdf=f"{SSA15_DIR}/comparison.pdf",
        comparison_png=report_figure(f"{SSA15_DIR}/comparison.png", "ssa15", "comparison"),
        claims=f"{SSA15_DIR}/claims.csv",
        macros=f"{SSA15_DIR}/macros.csv",
        timing_claims=f"{SSA15_DIR}/timing_claims.csv",
        timing_macros=f"{SSA15_DIR}/timing_macros.csv",
    params:
        section=config["ssa15"],
        seed_trackers=config["ssa_seeds"]["trackers"]["ssa15"],
    script:
        "../scripts/ssa15_figures.py"


SSA15_TARGETS = [*SSA15_RUN, *rules.ssa15_figures.output]


rule ssa15:
    input:
        SSA15_TARGETS,


ALL_TARGETS.extend(SSA15_TARGETS)
