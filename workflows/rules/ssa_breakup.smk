# A fresh breakup cloud (NASA standard breakup model on a bundled parent orbit) against the sparse catalogue:
# δ-GLMB, HOMHT k-best and R-FISST on the factored engine, GNN and JPDA on the same scans, scored as a catalogue
# operator would (cross-tags, completeness, purity, accuracy and covariance realism at re-acquisition, GOSPA).
# One job per tracker (each builds the same seeded scenarios), one density job, then one table/figure/ledger job.
SB_DIR = f"{RESULTS}/ssa_breakup"
SB_TRACKERS = config["ssa_breakup"]["trackers_run"]


rule ssa_breakup_run:
    output:
        cards=f"{SB_DIR}/runs/{{tracker}}_scorecard_timing.csv",
        sweep=f"{SB_DIR}/runs/{{tracker}}_ambiguity_sweep.csv",
    wildcard_constraints:
        tracker="|".join(SB_TRACKERS),
    params:
        cfg=config["ssa_breakup"],
        catalogue=config["ssa_catalogue"],
    script:
        "../scripts/ssa_breakup_run.py"


# The ambiguity output's p_min tuned on seeds of its own (ambiguity.tuning; experiments/ssa_breakup/tuning.py): the
# factored trackers and the reference run on the tuning seeds, the rule's table picks p_min, the table job keeps the
# evaluated seeds' outputs at that p_min. Without a tuning block ambiguity.p_min is used as given (the default's).
SB_TUNING = (config["ssa_breakup"].get("ambiguity") or {}).get("tuning") or {}
SB_TUNE_TRACKERS = SB_TUNING.get("trackers", []) if SB_TUNING.get("seeds") else []
SB_TUNE = [f"{SB_DIR}/tuning.csv"] if SB_TUNE_TRACKERS else []


rule ssa_breakup_tuning_run:
    output:
        cards=f"{SB_DIR}/tuning/{{tracker}}_scorecard_timing.csv",
        sweep=f"{SB_DIR}/tuning/{{tracker}}_ambiguity_sweep.csv",
    wildcard_constraints:
        tracker="|".join(SB_TUNE_TRACKERS) or "^$",
    params:
        cfg=config["ssa_breakup"],
        catalogue=config["ssa_catalogue"],
    script:
        "../scripts/ssa_breakup_tuning_run.py"


rule ssa_breakup_tuning:
    input:
        cards=expand(f"{SB_DIR}/tuning/{{tracker}}_scorecard_timing.csv", tracker=SB_TUNE_TRACKERS),
        sweeps=expand(f"{SB_DIR}/tuning/{{tracker}}_ambiguity_sweep.csv", tracker=SB_TUNE_TRACKERS),
    output:
        table=report_table(f"{SB_DIR}/tuning.csv", "ssa_breakup", "tuning"),
    params:
        cfg=config["ssa_breakup"],
    script:
        "../scripts/ssa_breakup_tuning.py"


# The committed ten-seed record (experiments/ssa_breakup/record.py: full.yaml + breakup_record.yaml), read back for
# the ledger's record rows and the paper's record macros when it exists.
SB_RECORD = [p for p in ["paper/record/ssa_breakup_record.csv"] if Path(p).exists()]


rule ssa_breakup_density:
    output:
        density=f"{SB_DIR}/density.csv",
        distances=f"{SB_DIR}/nn_distances.csv",
    params:
        cfg=config["ssa_breakup"],
        catalogue=config["ssa_catalogue"],
    script:
        "../scripts/ssa_breakup_density.py"


rule ssa_breakup_table:
    input:
        cards=expand(f"{SB_DIR}/runs/{{tracker}}_scorecard_timing.csv", tracker=SB_TRACKERS),
        sweeps=expand(f"{SB_DIR}/runs/{{tracker}}_ambiguity_sweep.csv", tracker=SB_TRACKERS),
        density=f"{SB_DIR}/density.csv",
        distances=f"{SB_DIR}/nn_distances.csv",
        tuning=SB_TUNE,
        record=SB_RECORD,
    output:
        scorecard=report_table(f"{SB_DIR}/scorecard.csv", "ssa_breakup", "scorecard"),
        summary=report_table(f"{SB_DIR}/summary.csv", "ssa_breakup", "summary"),
        timing=f"{SB_DIR}/summary_timing.csv",
        ratios=report_table(f"{SB_DIR}/ratios.csv", "ssa_breakup", "ratios"),
        ambiguity=report_table(f"{SB_DIR}/ambiguity_sweep.csv", "ssa_breakup", "ambiguity_sweep"),
        claims=f"{SB_DIR}/claims.csv",
        macros=f"{SB_DIR}/macros.csv",
        fig_pdf=f"{SB_DIR}/crosstags.pdf",
        fig_png=report_figure(f"{SB_DIR}/crosstags.png", "ssa_breakup", "crosstags"),
    params:
        cfg=config["ssa_breakup"],
    script:
        "../scripts/ssa_breakup_table.py"


SB_TARGETS = [*rules.ssa_breakup_table.output]


rule ssa_breakup:
    input:
        SB_TARGETS,


ALL_TARGETS.extend(SB_TARGETS)
