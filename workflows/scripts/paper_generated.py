"""Collect claims, the experiments' macros.csv files, the config's settings and figures into
{results}/paper/generated/ (thin wrapper over hypotrack.reporting.ledger)."""

import json
import subprocess
from pathlib import Path

import sys

from hypotrack.reporting.claim_sensitivity import write_sensitivity
from hypotrack.reporting.claim_tables import claim_count_macros, claims_summary_tex, sensitivity_tex
from hypotrack.reporting.claim_verdicts import claim_verdicts, headline, load_claims_file, placement_problems
from hypotrack.reporting.findings import findings_macros
from hypotrack.reporting.sections import gaps_tex, status_summary_tex
from hypotrack.reporting.ledger import (LiteralText, build_paper_inputs, config_macros, hard_problems, is_timing_table,
                                       ledger_problems, read_claims, timing_in_text)

commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                        check=False).stdout.strip()
# Claims, not rows: one verdict per claim of the documents (hypotrack.reporting.claim_verdicts), from the
# non-timing rows and the timing rows apart; the counts become macros, the table follows the abstract.
is_timing = [is_timing_table(p) for p in snakemake.input.claims]
ledger = read_claims([p for p, t in zip(snakemake.input.claims, is_timing) if not t])
timing = read_claims([p for p, t in zip(snakemake.input.claims, is_timing) if t])
spec = load_claims_file()
verdicts = claim_verdicts(ledger, spec, timing)
counts = headline(verdicts, ledger, spec, timing)
claims = build_paper_inputs(
    snakemake.input.claims,
    snakemake.input.figures,
    out_dir=Path(snakemake.output.macros).parent,
    results_dir=snakemake.params.results,
    extra_macros={"htCommit": LiteralText(commit or "unknown"),  # a hash such as 95e7490 is not a number
                  **config_macros(dict(snakemake.params.config)), **claim_count_macros(verdicts, counts),
                  **findings_macros(snakemake.params.results, ledger)},
    macros_paths=snakemake.input.macros,
)
# The report's generated text: status counts with every status defined, and every row that did not reproduce.
Path(snakemake.output.status_summary).write_text(status_summary_tex(claims))
Path(snakemake.output.gaps).write_text(gaps_tex(claims))
Path(snakemake.output.claims_summary).write_text(claims_summary_tex(verdicts, counts))
Path(snakemake.output.claims_sensitivity).write_text(
    sensitivity_tex(write_sensitivity(ledger, snakemake.output.sensitivity_csv, spec, timing), verdicts))
# Rows from timing claims files (*timing*claims.csv: speed-ups, throughput, run times) go to their own ledger so
# that ledger.csv is byte-identical for the same config and seed.
ledger.to_csv(snakemake.output.ledger, index=False)
timing.to_csv(snakemake.output.ledger_timing, index=False)
# The config this run computed with: `python -m hypotrack.reporting.record` records only a default run.
Path(snakemake.output.run_config).write_text(json.dumps(dict(snakemake.params.config), indent=1, sort_keys=True) + "\n")
# A failing row without a diagnosed cause is reported (the report lists it as not yet diagnosed); every other
# break of the ledger's rules fails the run: a verdict off the Monte Carlo rule, a reproduced or qualitative row
# without a negative control that fails, a row without evidence.
# A run time quoted in ledger.csv would make two runs of one config and seed differ: it fails the run too.
# A row the claims file does not place (a new experiment's row) is reported, not refused: the claims file is
# curated by hand (tests/unit/reporting/test_claim_verdicts.py checks it against the committed record).
for p in placement_problems(ledger, spec, timing):
    print(f"paper_generated: claims file: {p}", file=sys.stderr)
problems = ledger_problems(claims) + timing_in_text(ledger)
for p in problems:
    print(f"paper_generated: ledger: {p}", file=sys.stderr)
hard = hard_problems(problems)
if hard:
    raise SystemExit(f"paper_generated: {len(hard)} ledger rows break the rules (see above)")
