# Seed 000 Sec. IV-A, Figs 6, 8-11: R-FISST on the 50-object SSA scenario (45 objects in the initial
# hypothesis, 5 births). One sequential job per tracker (a filter cannot be split over time): the
# paper's chain alone and the chain + this project's completion step. The figures are drawn for the
# section's `primary` tracker; metrics, births, claims and the completion comparison cover every tracker.
# Config section: ssa50 (workflows/config/schema/ssa50.schema.yaml); scenario: rule ssa_scenario.
SSA50_DIR = f"{RESULTS}/ssa50"
SSA50_TRACKERS = list(config["ssa50"]["trackers"])
SSA50_TABLES = ["summary", "cardinality", "map_estimates", "weights", "timing"]
if config["ssa50"]["primary"] not in SSA50_TRACKERS:
    raise ValueError(f"ssa50.primary: {config['ssa50']['primary']!r} is not in ssa50.trackers {SSA50_TRACKERS}")


rule ssa50_run:
    wildcard_constraints:
        tracker="|".join(SSA50_TRACKERS),
    input:
        truth=f"{RESULTS}/ssa/ssa50_truth.csv",
        scans=f"{RESULTS}/ssa/ssa50_scans.csv",
        prior=f"{RESULTS}/ssa/ssa50_prior.csv",
    output:
        **{table: f"{SSA50_DIR}/{{tracker}}_{table}.csv" for table in SSA50_TABLES},
    log:
        f"{RESULTS}/logs/ssa50/{{tracker}}_run.log",
    params:
        # What the run reads (the script takes it from the config): a change reruns only this tracker.
        settings=lambda wc: {
            "master_seed": config["seed"],
            "tracker": config["ssa50"]["trackers"][wc.tracker],
            **{k: config["ssa50"][k] for k in ["max_hypotheses", "gate_probability", "population", "weight_snapshots"]},
        },
    script:
        "../scripts/ssa50_run.py"


SSA50_RUN = expand(f"{SSA50_DIR}/{{tracker}}_{{table}}.csv", tracker=SSA50_TRACKERS, table=SSA50_TABLES)


# The negative control of "E[N] before the first birth": the primary tracker with its clutter density 10^6 times
# too small (clutter returns become births), run up to the first birth.
rule ssa50_control_run:
    input:
        truth=f"{RESULTS}/ssa/ssa50_truth.csv",
        scans=f"{RESULTS}/ssa/ssa50_scans.csv",
        prior=f"{RESULTS}/ssa/ssa50_prior.csv",
    output:
        summary=f"{SSA50_DIR}/control_clutter_summary.csv",
    log:
        f"{RESULTS}/logs/ssa50/control_clutter_run.log",
    params:
        settings=lambda wc: {"master_seed": config["seed"], "primary": config["ssa50"]["primary"],
                             "tracker": config["ssa50"]["trackers"][config["ssa50"]["primary"]],
                             **{k: config["ssa50"][k] for k in ["max_hypotheses", "gate_probability", "population"]}},
    script:
        "../scripts/ssa50_control_run.py"


rule ssa50_figures:
    input:
        **{f"{tr}_{table}": f"{SSA50_DIR}/{tr}_{table}.csv" for tr in SSA50_TRACKERS for table in SSA50_TABLES},
        control_clutter=f"{SSA50_DIR}/control_clutter_summary.csv",
        truth=f"{RESULTS}/ssa/ssa50_truth.csv",
        scans=f"{RESULTS}/ssa/ssa50_scans.csv",
        prior=f"{RESULTS}/ssa/ssa50_prior.csv",
    output:
        metrics=report_table(f"{SSA50_DIR}/metrics.csv", "ssa50", "metrics"),
        births=report_table(f"{SSA50_DIR}/births.csv", "ssa50", "births"),
        control_metrics=f"{SSA50_DIR}/blind_metrics.csv",  # the negative control's per-scan metrics
        snapshots=f"{SSA50_DIR}/estimate_snapshots.csv",
        completion=report_table(f"{SSA50_DIR}/completion.csv", "ssa50", "completion"),
        completion_timing=f"{SSA50_DIR}/completion_timing.csv",
        fig6_pdf=f"{SSA50_DIR}/fig_6_weights.pdf",
        fig6_png=report_figure(f"{SSA50_DIR}/fig_6_weights.png", "ssa50", "fig_6_weights"),
        fig8_pdf=f"{SSA50_DIR}/fig_8_10_estimates.pdf",
        fig8_png=report_figure(f"{SSA50_DIR}/fig_8_10_estimates.png", "ssa50", "fig_8_10_estimates"),
        fig11_pdf=f"{SSA50_DIR}/fig_11_expected_number.pdf",
        fig11_png=report_figure(f"{SSA50_DIR}/fig_11_expected_number.png", "ssa50", "fig_11_expected_number"),
        ospa_pdf=f"{SSA50_DIR}/ospa.pdf",
        ospa_png=report_figure(f"{SSA50_DIR}/ospa.png", "ssa50", "ospa"),
        claims=f"{SSA50_DIR}/claims.csv",
        macros=f"{SSA50_DIR}/macros.csv",
        timing_claims=f"{SSA50_DIR}/timing_claims.csv",
        timing_macros=f"{SSA50_DIR}/timing_macros.csv",
    params:
        section=config["ssa50"],
        seed_trackers=config["ssa_seeds"]["trackers"]["ssa50"],
    script:
        "../scripts/ssa50_figures.py"


SSA50_TARGETS = [*SSA50_RUN, *rules.ssa50_control_run.output, *rules.ssa50_figures.output]


rule ssa50:
    input:
        SSA50_TARGETS,


ALL_TARGETS.extend(SSA50_TARGETS)


# Sensitivity of Fig. 11's P(N = 50) = 1 to the parameters 000 Sec. IV-A leaves out (clutter rate, p_D):
# one shard per setting runs the section's tracker (and the blind tracker, the control) on every scenario
# seed; the table rule applies the Monte Carlo rule per setting. Config: ssa50.sensitivity.
SSA50_SENS_DIR = f"{SSA50_DIR}/sensitivity"
SSA50_SENS_SETTINGS = range(len(config["ssa50"]["sensitivity"]["clutter_rates"])
                            * len(config["ssa50"]["sensitivity"]["p_D"]))


rule ssa50_sensitivity_setting:
    wildcard_constraints:
        setting=r"\d+",
    output:
        rows=f"{SSA50_SENS_DIR}/shards/setting_{{setting}}.csv",
        timing=f"{SSA50_SENS_DIR}/shards/setting_{{setting}}_timing.csv",
    params:
        # What a shard reads: a change of these reruns the shards.
        settings={"seed": config["seed"], "ssa": config["ssa"], "ssa50": config["ssa50"]},
    log:
        f"{RESULTS}/logs/ssa50/sensitivity_{{setting}}.log",
    script:
        "../scripts/ssa50_sensitivity_setting.py"


rule ssa50_sensitivity_table:
    input:
        rows=expand(f"{SSA50_SENS_DIR}/shards/setting_{{setting}}.csv", setting=SSA50_SENS_SETTINGS),
        timing=expand(f"{SSA50_SENS_DIR}/shards/setting_{{setting}}_timing.csv", setting=SSA50_SENS_SETTINGS),
    output:
        runs=f"{SSA50_SENS_DIR}/runs.csv",
        table=report_table(f"{SSA50_SENS_DIR}/p_end_grid.csv", "ssa50", "sensitivity"),
        timing=f"{SSA50_SENS_DIR}/sensitivity_timing.csv",
        claims=f"{SSA50_SENS_DIR}/claims.csv",
        macros=f"{SSA50_SENS_DIR}/macros.csv",
        fig_pdf=f"{SSA50_SENS_DIR}/p_end_grid.pdf",
        fig_png=report_figure(f"{SSA50_SENS_DIR}/p_end_grid.png", "ssa50", "sensitivity"),
    params:
        section=config["ssa50"]["sensitivity"],
        ssa=config["ssa"],
    script:
        "../scripts/ssa50_sensitivity_table.py"


SSA50_SENS_TARGETS = [*rules.ssa50_sensitivity_table.output]


rule ssa50_sensitivity:
    input:
        SSA50_SENS_TARGETS,


ALL_TARGETS.extend(SSA50_SENS_TARGETS)
