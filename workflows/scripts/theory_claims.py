"""Collect the ledger rows the theory notebooks recorded in their findings JSON (thin)."""
import json

from hypotrack.reporting.ledger import Claim, write_claims
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

claims = []
for path in snakemake.input.findings:  # noqa: F821
    with open(path) as fh:
        findings = json.load(fh)
    if not findings["all_passed"]:
        raise RuntimeError(f"{path}: a check failed, its claims cannot be reported")
    claims += [Claim(**row) for row in findings["claims"]]
write_claims(claims, snakemake.output.claims)  # noqa: F821
