"""The ssa_seeds ledger rows: each SSA verdict over scenario seeds with the ledger's Monte Carlo rule
(:func:`hypotrack.reporting.ledger.monte_carlo_claim`), from the per-seed table of :func:`.run.run_seed`."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd

from ...reporting.ledger import Claim, monte_carlo_claim
from ...reporting.verdict import with_control
from ..ssa import BLIND, BLIND_LABEL
from ..ssa.claims import OVER_SEEDS, seed_claim_id

__all__ = ["CHAIN_SUFFIX", "chain_seed_claims", "ssa_seeds_claims"]

#: The key suffix of a row over chain seeds: ``<case>_<tracker>_<test>Chains`` beside the scenario-seed row
#: ``<case>_<tracker>_<test>`` it is judged jointly with (``joint`` in the claims file).
CHAIN_SUFFIX = "Chains"


def _tests(case: str, g: pd.DataFrame, ref_label: str, births_label: str = ""):
    """The Monte Carlo tests of one case: ``(column, item, source, published, tolerance, key)``.

    ``births_label``: the births reference (HOMHT with document 000's births and deaths) a tracker
    with births and deaths is compared with too — the like-for-like pair with births and deaths.
    """
    if case == "ssa50":
        return [("expected_number_end", "E[N] at the end equals the true number", "000 Fig. 11",
                 g["n_catalogue_end"].mean(), 0.1, "ExpectedEnd"),
                ("p_n_end", "P(N = true number) at the end", "000 Fig. 11", 1.0, 0.05, "PEnd")]
    tests = []
    if ref_label:
        tests.append(("map_agreement", f"same MAP hypothesis as {ref_label} (fraction of scans)",
                      "000 Sec. V-A, Figs 12-14", 1.0, 0.01, "Agreement"))
    if births_label:
        tests.append(("map_agreement_births", f"same MAP hypothesis as {births_label} (fraction of scans)",
                      "000 Sec. V-A, Figs 12-14", 1.0, 0.01, "AgreementBirths"))
    return tests


def _mc_control(g: pd.DataFrame, col: str, published: float, tol: float, over: str = "seeds") -> tuple[str, bool]:
    """The blind tracker's value of a Monte Carlo test and whether it passes the same rule."""
    x = g[col].to_numpy(dtype=float)
    if len(x) < 2 or not np.isfinite(x).all():
        return "; ".join(f"{v:.4g}" for v in x), False
    c = monte_carlo_claim("control", "control", "control", float(published), x, abs_tol=tol, digits=4)
    return f"mean {float(c.mean):.4g} over {len(x)} {over} ({c.status})", c.status == "reproduced"


def ssa_seeds_claims(per_seed: pd.DataFrame) -> list:
    """Each SSA verdict over seeds (one stated Monte Carlo rule, :func:`monte_carlo_claim`).

    Published values: E[N] at the end equals the true number and the whole weight sits on it
    (000 Fig. 11, ssa50); R-FISST and HOMHT give the same estimates at every scan (000 Sec. V-A,
    ssa15) — against the fixed-number HOMHT (the reference) and, for the trackers with births and
    deaths, also against HOMHT with the same births and deaths (the births reference). Births tracked are counted over all seeds. With fewer than two seeds a row reports the
    single value as not decidable. The blind tracker's rows (:data:`~hypotrack.experiments.ssa.BLIND`)
    are the negative control: each test is run on them too and fills the row's ``control`` column
    (a passing row whose control also passes is *uninformative*).
    """
    return _claims(per_seed, "scenario seeds", "")


def chain_seed_claims(per_chain: pd.DataFrame) -> list:
    """The R-FISST verdicts of :func:`ssa_seeds_claims` over chain seeds (the table of
    :func:`.chains.run_chain_seed`: one realisation, the report's, and one MCMC stream per chain seed),
    with the same published values, tolerances and Monte Carlo rule; keys end in :data:`CHAIN_SUFFIX`
    and each row decides the same claim as its scenario-seed row (the claims file judges the two
    jointly: a verdict must hold over both sources of randomness)."""
    return _claims(per_chain.rename(columns={"chain_index": "seed_index"}), "chain seeds of the report's realisation",
                   CHAIN_SUFFIX)


def _claims(per_seed: pd.DataFrame, over: str, suffix: str) -> list:
    """The rows of :func:`ssa_seeds_claims` over ``over`` (seeds in ``seed_index``), keys ending in ``suffix``."""
    ex, claims = "ssa_seeds", []
    unit = over.split()[0]  # "scenario" / "chain": the kind of seed the notes count
    # the scenario-seed rows keep their words ("seeds"); the chain-seed rows name their kind of seed
    seeds, where = (f"{unit} seeds", f" (over {unit} seeds)") if suffix else ("seeds", "")
    if "births_reference" not in per_seed:  # a table without the pair with births and deaths
        per_seed = per_seed.assign(births_reference="", map_agreement_births=np.nan)
    # "" reads back as NaN
    per_seed = per_seed.assign(reference=per_seed["reference"].fillna(""),
                               births_reference=per_seed["births_reference"].fillna(""))
    names = dict(zip(zip(per_seed["case"], per_seed["tracker"]), per_seed["label"]))
    blind = {case: g for (case, tracker), g in per_seed.groupby(["case", "tracker"], sort=False) if tracker == BLIND}
    for (case, tracker), g in per_seed.groupby(["case", "tracker"], sort=False):
        if tracker == BLIND:
            continue
        label, n, ref, bref = g["label"].iloc[0], len(g), g["reference"].iloc[0], g["births_reference"].iloc[0]
        ctl = blind.get(case)
        key, ctl_over = f"{case}_{tracker}_", seeds
        # the chain-seed rows decide their own half of the claim (joined with the scenario seeds' in the claims
        # file): one verdict per row's claim id
        over_what = " (over chain seeds)" if suffix else ""
        for col, item, source, published, tol, k in _tests(case, g, names[(case, ref)] if ref else "",
                                                           names[(case, bref)] if bref else ""):
            x = g[col].to_numpy(dtype=float)
            if n >= 2 and np.isfinite(x).all():
                c = monte_carlo_claim(ex, f"{case}, {label}: {item}{where}", source, float(published), x,
                                      abs_tol=tol, digits=4, key=key + k + suffix,
                                      claim=_claim_id(case, tracker, k, names.get((case, bref), "")) + over_what,
                                      note=f"over {n} {over}; min {x.min():.4g}, median "
                                           f"{np.median(x):.4g}, max {x.max():.4g}")
            else:
                c = Claim(ex, f"{case}, {label}: {item}{where}", source, f"{published:.4g}",
                          "; ".join(f"{v:.4g}" for v in x), f"+/- {tol:g}", "inconclusive",
                          f"{n} {seeds[:-1]}(s): too few for a Monte Carlo verdict", "measurement", key=key + k + suffix)
            if k == "AgreementBirths":
                c = replace(c, note=f"{c.note}; {names[(case, bref)]}: Reid's factors for the objects and document "
                                    "000 Eq. 30's probabilities for births and deaths (this project's construction)")
            if ctl is not None:
                c = with_control(c, BLIND_LABEL, *_mc_control(ctl, col, published, tol, ctl_over))
            if k == "Agreement" and bref:
                # births and deaths against the fixed-number HOMHT: unlike models, so not document 000's
                # comparison (the like-for-like pairs are the fixed-number R-FISST's row and AgreementBirths)
                c = replace(c, status="extension", cause="", published="--", tolerance="--", z="", evidence="measurement",
                            note=f"{c.note}; unlike population models (births and deaths against a fixed number): "
                                 "measures how often R-FISST's birth model changes the MAP hypothesis, no verdict "
                                 f"on document 000's claim (decided against {names[(case, bref)]})")
            if c.status == "not reproduced" and col == "p_n_end":
                # the clutter rate and p_D document 000 does not state decide it (the ssa50 sensitivity grid)
                c = replace(c, cause="unstated parameter")
            claims.append(c)
        if g["births"].sum():
            tracked, total = int(g["births_tracked_end"].sum()), int(g["births"].sum())
            c = Claim(ex, f"{case}, {label}: every birth tracked at the end{where}", "000 Sec. IV-A",
                      "all", f"{tracked} of {total} births over {n} {seeds}", "all",
                      "reproduced" if tracked == total else "not reproduced",
                      f"latency (scans from first in view to a correct MAP track): median "
                      f"{np.nanmedian(g['birth_latency_mean']):.3g}, worst {np.nanmax(g['birth_latency_max']):.3g}",
                      "published number", key=key + "Births" + suffix, claim=_claim_id(case, tracker, "Births") + over_what)
            if ctl is not None:
                b_tracked, b_total = int(ctl["births_tracked_end"].sum()), int(ctl["births"].sum())
                c = with_control(c, BLIND_LABEL, f"{b_tracked} of {b_total} births", b_tracked == b_total)
            claims.append(c)
    return claims


_SINGLE_RUN_KEY = {"ExpectedEnd": ("ssa50", "ExpectedEnd"), "PEnd": ("ssa50", "PEnd"),
                   "Births": ("ssa50", "BirthsTracked"), "Agreement": ("ssa15", "SameMap")}


def _claim_id(case: str, tracker: str, key: str, births_label: str = "") -> str:
    """The claim id this over-seed row decides, shared with the single run's illustration row (the
    pair with births and deaths on both sides has no single run: its own id)."""
    if key == "AgreementBirths":
        return seed_claim_id(case, tracker, f"same MAP hypothesis as {births_label}")
    single_case, single_key = _SINGLE_RUN_KEY[key]
    return seed_claim_id(case, tracker, OVER_SEEDS[(single_case, single_key)])

