# The reproduction ledger (every experiment's claims.csv, collected by rule paper_generated) as an
# HTML table for `snakemake --report`: one section per experiment, rows coloured by status.
rule report_ledger:
    input:
        ledger=rules.paper_generated.output.ledger,
    output:
        html=report_figure(f"{RESULTS}/report/ledger.html", "ledger", "ledger", kind="Ledger"),
    script:
        "../scripts/report_ledger.py"


ALL_TARGETS.extend(rules.report_ledger.output)
