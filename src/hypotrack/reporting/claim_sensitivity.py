"""How much the claims' verdicts owe to tolerances chosen here: the verdicts under scaled tolerances.

Most tolerances are the project's choice (the claims file says so: ``tolerance.source: chosen here``).
For every such claim whose evidence holds Monte Carlo rows (n, mean, s.e. and a numeric published value,
or the same numbers in the claims file's ``note_monte_carlo``), :func:`tolerance_sensitivity` recomputes
each Monte Carlo row's status with :func:`~hypotrack.reporting.verdict.monte_carlo_verdict` at
:data:`FACTORS` times its tolerance, and the claim's verdict from them by the rule of
:mod:`.claim_verdicts`; :func:`sensitivity_summary` counts the claims whose verdict changes at each factor.
:func:`write_sensitivity` writes the table as CSV (the pipeline can call it beside the ledger);
:mod:`.claim_tables` renders it as Markdown and LaTeX.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from .claim_verdicts import claim_verdicts, evidence_table, load_claims_file, row_key, row_tolerance

__all__ = ["FACTORS", "SENSITIVITY_COLUMNS", "sensitivity_claims", "sensitivity_summary", "tolerance_sensitivity",
           "write_sensitivity"]

FACTORS = (0.25, 0.5, 1.0, 2.0, 4.0)
SENSITIVITY_COLUMNS = ["claim", "factor", "verdict", "changed", "rows"]


def sensitivity_claims(ledger: pd.DataFrame, spec: dict | None = None, timing: pd.DataFrame | None = None) -> list[str]:
    """Ids of the claims whose tolerance is chosen here and whose evidence holds a Monte Carlo row."""
    spec = spec or load_claims_file()
    frames = [ledger] if timing is None else [ledger, timing]
    rows = {row_key(r): r for f in frames for r in f.to_dict("records")}
    notes = {e["row"] for e in spec.get("note_monte_carlo", [])}
    table = evidence_table(ledger, spec, timing)
    out = []
    for c in spec["claims"]:
        if c["tolerance"]["source"] != "chosen here":
            continue
        keys = table.loc[table["claim"] == c["id"], "row"]
        if any(k in notes or row_tolerance(rows[k]) is not None for k in keys):
            out.append(c["id"])
    return out


def tolerance_sensitivity(ledger: pd.DataFrame, spec: dict | None = None, timing: pd.DataFrame | None = None,
                          factors=FACTORS) -> pd.DataFrame:
    """One row per (claim of :func:`sensitivity_claims`, factor): the verdict with every Monte Carlo row's
    tolerance times ``factor``, whether it differs from the verdict at factor 1, and the rows' statuses."""
    spec = spec or load_claims_file()
    ids = sensitivity_claims(ledger, spec, timing)
    base = claim_verdicts(ledger, spec, timing).set_index("id")["verdict"]
    out = []
    for factor in factors:
        scaled = {i: float(factor) for i in ids}
        verdicts = claim_verdicts(ledger, spec, timing, scaled).set_index("id")["verdict"]
        table = evidence_table(ledger, spec, timing, scaled)
        for i in ids:
            ev = table[table["claim"] == i]
            rows = "; ".join(f"{r['row']}: {r['status']}" for r in ev.to_dict("records"))
            out.append((i, float(factor), verdicts[i], verdicts[i] != base[i], rows))
    return pd.DataFrame(out, columns=SENSITIVITY_COLUMNS)


def sensitivity_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per factor: the number of claims in the table and of those whose verdict changes."""
    g = table.groupby("factor", sort=True)
    return pd.DataFrame({"factor": list(g.groups), "claims": g.size().to_list(),
                         "changed": g["changed"].sum().astype(int).to_list()})


def write_sensitivity(ledger: pd.DataFrame, path, spec: dict | None = None, timing: pd.DataFrame | None = None,
                      factors=FACTORS) -> pd.DataFrame:
    """Write :func:`tolerance_sensitivity` as CSV at ``path``; returns the table."""
    table = tolerance_sensitivity(ledger, spec, timing, factors)
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    table.to_csv(path, index=False)
    return table
