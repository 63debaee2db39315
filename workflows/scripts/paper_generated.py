"""Collect claims, the experiments' macros.csv files, the config's settings and figures into
{results}/paper/generated/ (thin wrapper over hypotrack.report)."""

import subprocess
from pathlib import Path

from hypotrack.report import build_paper_inputs, config_macros

commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                        check=False).stdout.strip()
claims = build_paper_inputs(
    snakemake.input.claims,
    snakemake.input.figures,
    out_dir=Path(snakemake.output.macros).parent,
    results_dir=snakemake.params.results,
    extra_macros={"htCommit": commit or "unknown", **config_macros(dict(snakemake.params.config))},
    macros_paths=snakemake.input.macros,
)
claims.to_csv(snakemake.output.ledger, index=False)
