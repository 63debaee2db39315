"""Collect claims, the experiments' macros.csv files and figures into paper/generated/ (thin wrapper over
hypotrack.report)."""

import subprocess

from hypotrack.report import build_paper_inputs

commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
claims = build_paper_inputs(
    snakemake.input.claims,
    snakemake.input.figures,
    out_dir="paper/generated",
    results_dir=snakemake.params.results,
    extra_macros={"htCommit": commit or "unknown"},
    macros_paths=snakemake.input.macros,
)
claims.to_csv(snakemake.output.ledger, index=False)
