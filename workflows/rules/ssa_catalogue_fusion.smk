# SSA catalogue, two sensors: the radar and the fence (Kwajalein, a thin elevation band) fused scan by scan in every
# tracker, against the radar alone on the same seeds; the operator's scorecard of the radar for both.
# Config: ssa_catalogue.fusion (n_objects, n_scans, trackers, fence). One job per tracker, then the table job.
if config["ssa_catalogue"].get("fusion"):
    SCF_TRACKERS = config["ssa_catalogue"]["fusion"]["trackers"]

    rule ssa_catalogue_fusion_run:
        output:
            cards=f"{SC_DIR}/fusion/{{tracker}}_cards_timing.csv",
        wildcard_constraints:
            tracker="|".join(SCF_TRACKERS),
        params:
            cfg=config["ssa_catalogue"],
            seed=SC_SEED,
        script:
            "../scripts/ssa_catalogue_fusion_run.py"

    rule ssa_catalogue_fusion:
        input:
            cards=expand(f"{SC_DIR}/fusion/{{tracker}}_cards_timing.csv", tracker=SCF_TRACKERS),
        output:
            table=report_table(f"{SC_DIR}/fusion.csv", "ssa_catalogue", "fusion"),
            timing=f"{SC_DIR}/fusion_timing.csv",
            claims=f"{SC_DIR}/fusion_claims.csv",
            macros=f"{SC_DIR}/fusion_macros.csv",
            pdf=f"{SC_DIR}/fusion.pdf",
            png=report_figure(f"{SC_DIR}/fusion.png", "ssa_catalogue", "fusion_figure"),
        script:
            "../scripts/ssa_catalogue_fusion.py"

    ALL_TARGETS.extend(rules.ssa_catalogue_fusion.output)
