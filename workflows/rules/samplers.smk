# R-FISST's chain (alone and with completion), the GLMB Gibbs sampler and Murty's k-best on
# identical association problems of the difficulty axis: posterior mass captured (exact, by
# enumeration), MAP found and distinct children per second, at equal proposal budgets; also on
# association problems recorded from the GLMB benchmark's scans.
SAMPLERS_DIR = f"{RESULTS}/samplers"


rule samplers_sweep:
    input:
        # association problems recorded from the GLMB benchmark's scans (rule glmb_benchmark_record)
        recorded=f"{RESULTS}/glmb_benchmark/recorded_problems.npz",
    output:
        raw=f"{SAMPLERS_DIR}/raw_timing.csv",
        summary=report_table(f"{SAMPLERS_DIR}/summary.csv", "samplers", "summary"),
        timing=f"{SAMPLERS_DIR}/summary_timing.csv",
        fig_pdf=f"{SAMPLERS_DIR}/mass_vs_budget.pdf",
        fig_png=report_figure(f"{SAMPLERS_DIR}/mass_vs_budget.png", "samplers", "mass_vs_budget"),
        claims=f"{SAMPLERS_DIR}/claims.csv",
        macros=f"{SAMPLERS_DIR}/macros.csv",
        timing_macros=f"{SAMPLERS_DIR}/timing_macros.csv",
        time_to_mass=f"{SAMPLERS_DIR}/time_to_mass_timing.csv",
        compute_claims=f"{SAMPLERS_DIR}/compute_timing_claims.csv",  # wall-time verdicts: not byte-reproducible
    params:
        cfg=config["samplers"],
        seed=config["seed"],
    script:
        "../scripts/samplers_sweep.py"


SAMPLERS_TARGETS = [*rules.samplers_sweep.output]


rule samplers:
    input:
        SAMPLERS_TARGETS,


ALL_TARGETS.extend(SAMPLERS_TARGETS)
