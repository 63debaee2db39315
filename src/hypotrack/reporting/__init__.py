"""Reporting: the ledger and its verdict rule, README generation, paper inputs, run timing, job logs.

Modules
-------
ledger         claims, the verdict rule, ledger checks and the ledger's LaTeX/Markdown/HTML forms
claim_verdicts one verdict per claim of the documents, from its ledger rows (claims file: document_claims.yaml)
claim_sensitivity  the claims' verdicts under scaled tolerances (the tolerances chosen here)
claim_tables   the claims' headline, per-document table and sensitivity as Markdown and LaTeX
readme         the README's generated blocks, from the committed record
paper          checks and build of the report PDF
pipeline_time  what a pipeline run cost, from Snakemake's job benchmarks
joblog         every line a pipeline job prints names the job
"""
