# Seed 001's numeric claims, from the formulas and from the hypothesis engine's own weights:
# the undetected-birth weight ratio (1 - p_D) alpha (Eq. 39), the Eq. 43 bound one scan later,
# and FISST = HOMHT for a fixed number of targets (Sec. V-A); and the engine's one-scan posterior against
# an independent brute-force oracle of the seeds' densities. Small exhaustive problems: no shards.
BS_DIR = f"{RESULTS}/belief_space"


rule belief_space_ratio:
    output:
        table=report_table(f"{BS_DIR}/undetected_birth_ratio.csv", "belief_space", "ratio_table"),
    params:
        cfg=config["belief_space"],
    script:
        "../scripts/belief_space_ratio.py"


rule belief_space_eq43:
    output:
        offsets=f"{BS_DIR}/eq43_across_pixel.csv",
        noise=f"{BS_DIR}/eq43_vs_noise.csv",
    params:
        cfg=config["belief_space"],
    script:
        "../scripts/belief_space_eq43.py"


rule belief_space_equivalence:
    output:
        table=report_table(f"{BS_DIR}/fisst_vs_homht.csv", "belief_space", "equivalence_table"),
    params:
        cfg=config["belief_space"],
        seed=config["belief_space"]["seed"],
    script:
        "../scripts/belief_space_equivalence.py"


rule belief_space_oracle:
    output:
        table=report_table(f"{BS_DIR}/oracle.csv", "belief_space", "oracle_table"),
    params:
        cfg=config["belief_space"]["oracle"],
        seed=config["belief_space"]["seed"],
    script:
        "../scripts/belief_space_oracle.py"


rule belief_space_report:
    input:
        ratio=rules.belief_space_ratio.output.table,
        offsets=rules.belief_space_eq43.output.offsets,
        noise=rules.belief_space_eq43.output.noise,
        equivalence=rules.belief_space_equivalence.output.table,
        oracle=rules.belief_space_oracle.output.table,
    output:
        ratio_pdf=f"{BS_DIR}/undetected_birth_ratio.pdf",
        ratio_png=report_figure(f"{BS_DIR}/undetected_birth_ratio.png", "belief_space", "undetected_birth_ratio"),
        eq43_pdf=f"{BS_DIR}/eq43_bound.pdf",
        eq43_png=report_figure(f"{BS_DIR}/eq43_bound.png", "belief_space", "eq43_bound"),
        equivalence_pdf=f"{BS_DIR}/fisst_vs_homht.pdf",
        equivalence_png=report_figure(f"{BS_DIR}/fisst_vs_homht.png", "belief_space", "fisst_vs_homht"),
        checks=f"{BS_DIR}/checks.csv",
        claims=f"{BS_DIR}/claims.csv",
    params:
        cfg=config["belief_space"],
    script:
        "../scripts/belief_space_report.py"


BS_TARGETS = [
    *rules.belief_space_ratio.output,
    *rules.belief_space_eq43.output,
    *rules.belief_space_equivalence.output,
    *rules.belief_space_oracle.output,
    *rules.belief_space_report.output,
]


rule belief_space:
    input:
        BS_TARGETS,


ALL_TARGETS.extend(BS_TARGETS)
