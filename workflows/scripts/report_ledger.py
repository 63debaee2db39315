"""Render the ledger CSV as one HTML page for the Snakemake report (thin wrapper over hypotrack.reporting.ledger)."""

import pandas as pd
from hypotrack.reporting.joblog import prefix_output
from hypotrack.reporting.ledger import claims_html

prefix_output(snakemake)  # every line this job prints names the job

ledger = pd.read_csv(snakemake.input.ledger, dtype=str, keep_default_na=False)
with open(snakemake.output.html, "w") as f:
    f.write(claims_html(ledger))
