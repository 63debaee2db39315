# Seed 000 Sec. IV-A, Figs 6, 8-11: R-FISST on the 50-object SSA scenario (45 objects in the initial
# hypothesis, 5 births). The tracker run is one sequential job (a filter cannot be split over time);
# the figures, metrics and claims are drawn from its tables.
# Config section: ssa50 (workflows/config/schema/ssa50.schema.yaml); scenario: rule ssa_scenario.
SSA50_DIR = f"{RESULTS}/ssa50"
SSA50_RUN = {
    table: f"{SSA50_DIR}/rfisst_{table}.csv" for table in ["summary", "cardinality", "map_estimates", "weights"]
}


rule ssa50_run:
    input:
        truth=f"{RESULTS}/ssa/ssa50_truth.csv",
        scans=f"{RESULTS}/ssa/ssa50_scans.csv",
        prior=f"{RESULTS}/ssa/ssa50_prior.csv",
    output:
        **SSA50_RUN,
    log:
        f"{RESULTS}/logs/ssa50/rfisst_run.log",
    params:
        # What the run reads (the script takes it from the config): figure settings do not rerun it.
        settings={
            "master_seed": config["seed"],
            **{k: config["ssa50"][k] for k in
               ["max_hypotheses", "gate_probability", "trackers", "population", "weight_snapshots"]},
        },
    script:
        "../scripts/ssa50_run.py"


rule ssa50_figures:
    input:
        **SSA50_RUN,
        truth=f"{RESULTS}/ssa/ssa50_truth.csv",
        scans=f"{RESULTS}/ssa/ssa50_scans.csv",
        prior=f"{RESULTS}/ssa/ssa50_prior.csv",
    output:
        metrics=report_table(f"{SSA50_DIR}/metrics.csv", "ssa50", "metrics"),
        births=report_table(f"{SSA50_DIR}/births.csv", "ssa50", "births"),
        snapshots=f"{SSA50_DIR}/estimate_snapshots.csv",
        fig6_pdf=f"{SSA50_DIR}/fig_6_weights.pdf",
        fig6_png=report_figure(f"{SSA50_DIR}/fig_6_weights.png", "ssa50", "fig_6_weights"),
        fig8_pdf=f"{SSA50_DIR}/fig_8_10_estimates.pdf",
        fig8_png=report_figure(f"{SSA50_DIR}/fig_8_10_estimates.png", "ssa50", "fig_8_10_estimates"),
        fig11_pdf=f"{SSA50_DIR}/fig_11_expected_number.pdf",
        fig11_png=report_figure(f"{SSA50_DIR}/fig_11_expected_number.png", "ssa50", "fig_11_expected_number"),
        ospa_pdf=f"{SSA50_DIR}/ospa.pdf",
        ospa_png=report_figure(f"{SSA50_DIR}/ospa.png", "ssa50", "ospa"),
        claims=f"{SSA50_DIR}/claims.csv",
    params:
        section=config["ssa50"],
    script:
        "../scripts/ssa50_figures.py"


SSA50_TARGETS = [*SSA50_RUN.values(), *rules.ssa50_figures.output]


rule ssa50:
    input:
        SSA50_TARGETS,


ALL_TARGETS.extend(SSA50_TARGETS)
