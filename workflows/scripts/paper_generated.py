"""Collect claims, the experiments' macros.csv files, the config's settings and figures into
{results}/paper/generated/ (thin wrapper over hypotrack.reporting.ledger)."""

import json
import subprocess
from pathlib import Path

import sys

from hypotrack.reporting.sections import gaps_tex, status_summary_tex
from hypotrack.reporting.ledger import (LiteralText, build_paper_inputs, config_macros, hard_problems, is_timing_table,
                                       ledger_problems, read_claims, timing_in_text)

commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                        check=False).stdout.strip()
claims = build_paper_inputs(
    snakemake.input.claims,
    snakemake.input.figures,
    out_dir=Path(snakemake.output.macros).parent,
    results_dir=snakemake.params.results,
    extra_macros={"htCommit": LiteralText(commit or "unknown"),  # a hash such as 95e7490 is not a number
                  **config_macros(dict(snakemake.params.config))},
    macros_paths=snakemake.input.macros,
)
# The report's generated text: status counts with every status defined, and every row that did not reproduce.
Path(snakemake.output.status_summary).write_text(status_summary_tex(claims))
Path(snakemake.output.gaps).write_text(gaps_tex(claims))
# Rows from timing claims files (*timing*claims.csv: speed-ups, throughput, run times) go to their own ledger so
# that ledger.csv is byte-identical for the same config and seed.
is_timing = [is_timing_table(p) for p in snakemake.input.claims]
ledger = read_claims([p for p, t in zip(snakemake.input.claims, is_timing) if not t])
ledger.to_csv(snakemake.output.ledger, index=False)
read_claims([p for p, t in zip(snakemake.input.claims, is_timing) if t]).to_csv(snakemake.output.ledger_timing,
                                                                                  index=False)
# The config this run computed with: `python -m hypotrack.reporting.record` records only a default run.
Path(snakemake.output.run_config).write_text(json.dumps(dict(snakemake.params.config), indent=1, sort_keys=True) + "\n")
# A failing row without a diagnosed cause is reported (the report lists it as not yet diagnosed); every other
# break of the ledger's rules fails the run: a verdict off the Monte Carlo rule, a reproduced or qualitative row
# without a negative control that fails, a row without evidence.
# A run time quoted in ledger.csv would make two runs of one config and seed differ: it fails the run too.
problems = ledger_problems(claims) + timing_in_text(ledger)
for p in problems:
    print(f"paper_generated: ledger: {p}", file=sys.stderr)
hard = hard_problems(problems)
if hard:
    raise SystemExit(f"paper_generated: {len(hard)} ledger rows break the rules (see above)")
