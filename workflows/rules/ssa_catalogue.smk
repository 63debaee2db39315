from pathlib import Path

# SSA at catalogue scale: real TLE objects (SGP4 truth) seen by a ground radar; δ-GLMB, HOMHT k-best and
# R-FISST on the factored engine, GNN and JPDA on the same scans; cost against N, GOSPA, continuity, births.
# One job per tracker (each simulates the same seeded scenarios), then one table/figure/ledger job.
SC_DIR = f"{RESULTS}/ssa_catalogue"
SC_TRACKERS = config["ssa_catalogue"]["trackers_run"]
# Every run of the experiment is the evaluated one: another seed and time window than the model was tuned on
# (ssa_catalogue.tuning; the window's start offset is read from the section by build_scenario).
SC_SEED = config["ssa_catalogue"].get("tuning", {}).get("evaluated_on", {}).get("seed", config["seed"])


rule ssa_catalogue_run:
    output:
        per_scan=f"{SC_DIR}/runs/{{tracker}}_per_scan_timing.csv",
        assign=f"{SC_DIR}/runs/{{tracker}}_assign.csv",
        memory=f"{SC_DIR}/runs/{{tracker}}_memory_timing.csv",
        card=f"{SC_DIR}/runs/{{tracker}}_scorecard_timing.csv",
    wildcard_constraints:
        tracker="|".join(SC_TRACKERS),
    params:
        cfg=config["ssa_catalogue"],
        seed=SC_SEED,
    script:
        "../scripts/ssa_catalogue_run.py"


rule ssa_catalogue_parallel:
    output:
        timing=f"{SC_DIR}/parallel_timing.csv",
    params:
        cfg=config["ssa_catalogue"],
        seed=SC_SEED,
    threads: config["ssa_catalogue"]["parallel"]["workers"]
    script:
        "../scripts/ssa_catalogue_parallel.py"


# hypotrack's GNN/JPDA against Stone Soup's on the same catalogue scans (without Stone Soup: hypotrack alone)
rule ssa_catalogue_peers:
    output:
        timing=f"{SC_DIR}/peers_timing.csv",
    params:
        cfg=config["ssa_catalogue"],
        seed=SC_SEED,
    script:
        "../scripts/ssa_catalogue_peers.py"


rule ssa_catalogue_table:
    input:
        parallel=f"{SC_DIR}/parallel_timing.csv",
        peers=f"{SC_DIR}/peers_timing.csv",
        per_scan=expand(f"{SC_DIR}/runs/{{tracker}}_per_scan_timing.csv", tracker=SC_TRACKERS),
        assign=expand(f"{SC_DIR}/runs/{{tracker}}_assign.csv", tracker=SC_TRACKERS),
        memory=expand(f"{SC_DIR}/runs/{{tracker}}_memory_timing.csv", tracker=SC_TRACKERS),
    output:
        summary=report_table(f"{SC_DIR}/summary.csv", "ssa_catalogue", "summary"),
        timing=f"{SC_DIR}/summary_timing.csv",
        claims=f"{SC_DIR}/claims.csv",
        timing_claims=f"{SC_DIR}/timing_claims.csv",
        macros=f"{SC_DIR}/macros.csv",
        timing_macros=f"{SC_DIR}/timing_macros.csv",
        cost_pdf=f"{SC_DIR}/cost.pdf",
        cost_png=report_figure(f"{SC_DIR}/cost.png", "ssa_catalogue", "cost"),
        groups_pdf=f"{SC_DIR}/groups.pdf",
        groups_png=report_figure(f"{SC_DIR}/groups.png", "ssa_catalogue", "groups"),
        catalogue_pdf=f"{SC_DIR}/catalogue.pdf",
        catalogue_png=report_figure(f"{SC_DIR}/catalogue.png", "ssa_catalogue", "catalogue"),
        run_config=f"{SC_DIR}/run_config.json",
    params:
        cfg=config["ssa_catalogue"],
        seed=SC_SEED,
    script:
        "../scripts/ssa_catalogue_table.py"


SC_TARGETS = [*rules.ssa_catalogue_table.output]


# The operator's scorecard (ssa_breakup's, from the same runs): table, figure, ledger rows and macros.
rule ssa_catalogue_scorecard:
    input:
        cards=expand(f"{SC_DIR}/runs/{{tracker}}_scorecard_timing.csv", tracker=SC_TRACKERS),
    output:
        table=report_table(f"{SC_DIR}/scorecard.csv", "ssa_catalogue", "scorecard"),
        claims=f"{SC_DIR}/scorecard_claims.csv",
        macros=f"{SC_DIR}/scorecard_macros.csv",
        pdf=f"{SC_DIR}/scorecard.pdf",
        png=report_figure(f"{SC_DIR}/scorecard.png", "ssa_catalogue", "scorecard"),
    params:
        cfg=config["ssa_catalogue"],
    script:
        "../scripts/ssa_catalogue_scorecard.py"


SC_TARGETS.extend(rules.ssa_catalogue_scorecard.output)


# Document 000's single-event population (Eq. 30: one birth or death per scan for the whole scene) through the
# factored engine, which applies it per group: R-FISST unfactored, factored, and unfactored with another chain
# seed (the noise floor) on the ssa50 scans. Config: ssa_catalogue.single_event (and ssa50's tracker).
rule ssa_catalogue_single_event:
    input:
        truth=f"{RESULTS}/ssa/ssa50_truth.csv",
        scans=f"{RESULTS}/ssa/ssa50_scans.csv",
        prior=f"{RESULTS}/ssa/ssa50_prior.csv",
    output:
        per_scan=f"{SC_DIR}/single_event.csv",
        summary=f"{SC_DIR}/single_event_summary.csv",
        timing=f"{SC_DIR}/single_event_timing.csv",
        claims=f"{SC_DIR}/single_event_claims.csv",
        macros=f"{SC_DIR}/single_event_macros.csv",
    params:
        # What the script reads (from the config): a change of these reruns the job.
        settings={"seed": config["seed"], "ssa": config["ssa"], "ssa50": config["ssa50"],
                  "single_event": config["ssa_catalogue"]["single_event"]},
    log:
        f"{RESULTS}/logs/ssa_catalogue/single_event.log",
    script:
        "../scripts/ssa_catalogue_single_event.py"


SC_TARGETS.extend(rules.ssa_catalogue_single_event.output)

# The committed whole-catalogue record (a full.yaml run, recorded by `python -m
# hypotrack.experiments.ssa_catalogue.record <results>`): its macros let the report quote it. Read only;
# absent, the report says it is not recorded.
SC_FULL_RECORD = "paper/record/ssa_catalogue_full.csv"
SC_SCALE_RECORD = "paper/record/ssa_catalogue_scale.csv"  # its timing at scale, when recorded
if Path(SC_FULL_RECORD).exists():

    rule ssa_catalogue_full_record:
        input:
            SC_FULL_RECORD,
            scale=[SC_SCALE_RECORD] if Path(SC_SCALE_RECORD).exists() else [],
        output:
            macros=f"{SC_DIR}/full_record_macros.csv",
        params:
            goal=config["ssa_catalogue"]["cpu_per_object_goal_ms"],
        script:
            "../scripts/ssa_catalogue_full_record.py"

    SC_TARGETS.append(rules.ssa_catalogue_full_record.output.macros)


# Honest timing at scale: each tracker on cloned populations of several sizes (ssa_catalogue.scale), one
# process per run (its own peak memory), the median of the runs with their spread, slopes of cost against N.
if config["ssa_catalogue"].get("scale"):

    rule ssa_catalogue_scale:
        output:
            runs=f"{SC_DIR}/scale_runs_timing.csv",
            summary=f"{SC_DIR}/scale_summary_timing.csv",
        params:
            cfg=config["ssa_catalogue"],
            seed=SC_SEED,
        script:
            "../scripts/ssa_catalogue_scale.py"

    SC_TARGETS.extend(rules.ssa_catalogue_scale.output)


rule ssa_catalogue:
    input:
        SC_TARGETS,


ALL_TARGETS.extend(SC_TARGETS)


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
