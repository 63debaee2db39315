"""Render the ledger CSV as one HTML page (thin: pandas does the table)."""

import html

import pandas as pd
from hypotrack.experiments.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

STATUS_COLOURS = {"reproduced": "#e6f4ea", "not reproduced": "#fce8e6", "qualitative": "#fef7e0"}

ledger = pd.read_csv(snakemake.input.ledger, dtype=str, keep_default_na=False)
status = "status" if "status" in ledger.columns else None
parts = [
    "<!DOCTYPE html><html><head><meta charset='utf-8'><title>hypotrack ledger</title><style>"
    "body{font-family:sans-serif;font-size:13px} table{border-collapse:collapse;margin-bottom:1.5em}"
    "td,th{border:1px solid #ccc;padding:3px 6px;vertical-align:top;text-align:left}</style></head><body>",
    f"<h2>Reproduction ledger: {len(ledger)} claims</h2>",
]
if status:
    counts = ledger[status].value_counts().sort_index()
    parts.append("<p>" + ", ".join(f"{html.escape(k)}: {v}" for k, v in counts.items()) + "</p>")
for experiment, rows in ledger.groupby("experiment", sort=False):
    rows = rows.drop(columns="experiment")
    styled = rows.style.hide(axis="index")
    if status:
        styled = styled.apply(
            lambda r: [f"background-color:{STATUS_COLOURS.get(r[status], '#ffffff')}"] * len(r), axis=1
        )
    parts += [f"<h3>{html.escape(experiment)}</h3>", styled.to_html(escape="html")]
parts.append("</body></html>")
with open(snakemake.output.html, "w") as f:
    f.write("\n".join(parts))
