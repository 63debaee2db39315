"""SSA verdicts over scenario seeds: ssa50 and ssa15 (document 000 Sec. IV-A, V-A) as a Monte Carlo.

The ``ssa50`` and ``ssa15`` experiments judge one realisation each; a verdict such as "P(N = 50) at
the end is 1" or "R-FISST and HOMHT agree at every scan" may be that realisation's luck. This
experiment draws ``n_seeds`` independent realisations of both scenarios (objects, births, clutter,
initial hypothesis) and runs the same named trackers on each — R-FISST as the paper's chain alone
and with this project's completion step, and on ssa15 HOMHT and R-FISST with the number of objects
fixed like HOMHT's (the like-for-like pair without births and deaths), and HOMHT with document 000's
births and deaths (Eq. 30), the population R-FISST runs with (the like-for-like pair with births and
deaths; ``ssa_seeds.extra_trackers``, ``ssa_seeds.births_reference``) — one shard per seed. The blind tracker
(:func:`hypotrack.experiments.ssa.blind_run`: EKF prediction of the initial hypothesis, no
measurement used, no births) runs on every realisation as the negative control of each verdict.

Steps: :func:`seed_scenario` draws realisation ``i``; :func:`run_seed` runs every tracker on both
cases and reduces each run to one row of :data:`SEED_COLUMNS`; :func:`distribution_table` gives
the distribution over seeds (quantiles, min, max, mean and standard error);
:func:`ssa_seeds_claims` states each SSA verdict over seeds with the ledger's Monte Carlo rule
(:func:`hypotrack.reporting.ledger.monte_carlo_claim`); :func:`plot_distributions` draws them.

Seeds: realisation ``i`` of case ``c`` uses child ``i`` of ``experiment_seeds(seed, "ssa_seeds/c")``
and tracker ``t`` on it the stream ``"ssa_seeds/c/i/t"``: a seed's result does not depend on how
many seeds are run.
"""

from __future__ import annotations

import textwrap

import time
from collections.abc import Callable, Mapping
from dataclasses import replace

import numpy as np
import pandas as pd

from ..._validation import check_int
from ...reporting.ledger import Claim, monte_carlo_claim
from ...reporting.verdict import with_control
from ...scenarios.ssa import SSAScenario, params_from_config, simulate_ssa
from ..seeds import experiment_seeds
from ..ssa.claims import OVER_SEEDS, seed_claim_id
from ..ssa import (BLIND, BLIND_LABEL, OSPASettings, TrackerSettings, birth_recognition, blind_run, evaluate_map,
                   make_tracker, map_agreement, run_tracker)

__all__ = ["CASES", "METRICS", "SEED_COLUMNS", "distribution_table", "plot_distributions", "run_seed",
           "seed_scenario", "ssa_seeds_claims", "tracker_settings"]

CASES = ("ssa50", "ssa15")
SEED_COLUMNS = ["case", "seed_index", "tracker", "label", "n_scans", "n_catalogue_end", "expected_number_end",
                "expected_number_error", "p_n_end", "births", "births_tracked_end", "birth_latency_mean", "birth_latency_max", "reference",
                "map_agreement", "births_reference", "map_agreement_births", "ospa_in_view_mean", "ospa_catalogue_mean",
                "children_per_scan_mean"]
#: Per-seed metrics summarised over seeds, with their meaning (figure labels).
METRICS = {
    "p_n_end": "P(N = true number) at the end",
    "expected_number_error": "E[N] minus the true number at the end",
    "births_tracked_end": "births tracked at the end",
    "birth_latency_mean": "mean scans from first in view to a correct track",
    "map_agreement": "fraction of scans with the reference's MAP hypothesis",
    "map_agreement_births": "fraction of scans with the MAP hypothesis of the reference with births and deaths",
    "ospa_in_view_mean": "mean OSPA in view (km)",
}


def seed_scenario(config: Mapping, case: str, index: int) -> SSAScenario:
    """Realisation ``index`` of SSA ``case`` under the config's ``ssa`` section (its ``n_scans``
    overridden by ``ssa_seeds.n_scans`` when set)."""
    if case not in CASES:
        raise ValueError(f"case must be one of {CASES}, got {case!r}")
    index = check_int(index, "index", minimum=0)
    section = dict(config["ssa"])
    if config["ssa_seeds"].get("n_scans"):
        section["n_scans"] = config["ssa_seeds"]["n_scans"]
    params = params_from_config(section, case)
    return simulate_ssa(params, experiment_seeds(config["seed"], f"ssa_seeds/{case}", index + 1)[index])


def tracker_settings(config: Mapping, case: str) -> dict:
    """The trackers ``ssa_seeds.trackers[case]`` as configured in the ``case`` section (or, for
    those run over seeds only, in ``ssa_seeds.extra_trackers[case]``, with the case section's
    ``max_hypotheses``, gate and population), with the MCMC proposals per parent overridden by
    ``ssa_seeds.n_steps`` when set."""
    own = config["ssa_seeds"]
    section = dict(config[case])
    extra = (own.get("extra_trackers") or {}).get(case) or {}
    clash = set(extra) & set(section.get("trackers", {}))
    if clash:
        raise ValueError(f"ssa_seeds.extra_trackers.{case} must not redefine {case}.trackers, got {sorted(clash)}")
    section["trackers"] = {**section.get("trackers", {}), **extra}
    out = {}
    for name in own["trackers"][case]:
        s = TrackerSettings.from_config(section, name)
        if own.get("n_steps") and s.kind == "rfisst":
            s = s.with_options(n_steps=int(own["n_steps"]))
        out[name] = s
    return out


def _row(case, index, name, label, scenario, run, section, reference_map, reference, births_map=None,
         births_reference=""):
    metrics, matched = evaluate_map(run.map_estimates, scenario, ospa_settings=OSPASettings(**section["ospa"]),
                                    error_bound_probability=section["error_bound_probability"])
    births = birth_recognition(matched, scenario)
    last = int(run.summary["scan"].max())
    n_end = int(metrics["n_catalogue"].iloc[-1])
    card = run.cardinality[run.cardinality["scan"] == last]
    delays = births.loc[births["delay_scans"] >= 0, "delay_scans"]
    agreement = np.nan
    if reference_map is not None:
        agreement = float(map_agreement(run.map_estimates, reference_map, scenario.prior_ids)["agree"].mean())
    return {
        "case": case, "seed_index": index, "tracker": name, "label": label, "n_scans": last + 1,
        "n_catalogue_end": n_end, "expected_number_end": float(run.summary["expected_number"].iloc[-1]),
        "expected_number_error": float(run.summary["expected_number"].iloc[-1]) - n_end,
        "p_n_end": float(card.loc[card["n_objects"] == n_end, "probability"].sum()),
        "births": len(births), "births_tracked_end": int(births["tracked_at_end"].sum()),
        "birth_latency_mean": float(delays.mean()) if len(delays) else np.nan,
        "birth_latency_max": float(delays.max()) if len(delays) else np.nan,
        "reference": reference if reference_map is not None else "", "map_agreement": agreement,
        "births_reference": births_reference if births_map is not None else "",
        "map_agreement_births": (float(map_agreement(run.map_estimates, births_map, scenario.prior_ids)["agree"].mean())
                                 if births_map is not None else np.nan),
        "ospa_in_view_mean": float(np.nanmean(metrics["ospa_in_view"])),
        "ospa_catalogue_mean": float(metrics["ospa_catalogue"].mean()),
        "children_per_scan_mean": float(run.summary.loc[run.summary["scan"] > 0, "n_children"].mean()),
    }


def _reference(config, case, settings):
    """ssa15: the configured reference (HOMHT); ssa50: the paper's chain (the first tracker)."""
    ref = config["ssa_seeds"].get("reference", {}).get(case)
    return ref if ref in settings else next(iter(settings))


def _births_reference(config, case, settings):
    """The configured tracker with births and deaths (``ssa_seeds.births_reference[case]``) that the
    trackers with births and deaths are compared with too, or ``None``."""
    ref = (config["ssa_seeds"].get("births_reference") or {}).get(case)
    if ref is None:
        return None
    if ref not in settings:  # defined but not run (ssa_seeds.trackers names a subset): no such pair
        defined = {*config[case].get("trackers", {}), *((config["ssa_seeds"].get("extra_trackers") or {}).get(case) or {})}
        if ref in defined:
            return None
        raise ValueError(f"ssa_seeds.births_reference.{case} must be one of the case's trackers {sorted(defined)}, "
                         f"got {ref!r}")
    if not settings[ref].population:
        raise ValueError(f"ssa_seeds.births_reference.{case}: {ref!r} must run with births and deaths (population true)")
    return ref


def run_seed(config: Mapping, index: int, progress: Callable[[str], None] | None = print):
    """Every configured tracker on realisation ``index`` of both cases.

    Returns ``(rows, timing)``: one :data:`SEED_COLUMNS` row per case and tracker, and one for the
    blind tracker (:data:`~hypotrack.experiments.ssa.BLIND`, the negative control of every check:
    EKF prediction of the initial hypothesis, no measurements, no births), deterministic given the
    config; and ``case, seed_index, tracker, seconds, cpu_seconds``.

    Every tracker but the reference is compared with the reference's MAP hypothesis; every tracker
    with births and deaths (and the blind tracker, the control) also with the births reference's
    (``births_reference``, ``map_agreement_births``), which itself has no row against the reference.
    """
    rows, timing = [], []
    for case in config["ssa_seeds"]["trackers"]:
        scenario = seed_scenario(config, case, index)
        settings = tracker_settings(config, case)
        ref = _reference(config, case, settings)
        bref = _births_reference(config, case, settings)
        runs = {}
        for name in [ref, *[n for n in settings if n != ref]]:  # the reference first: the others compare
            s = settings[name]
            rng = np.random.default_rng(experiment_seeds(config["seed"], f"ssa_seeds/{case}/{index}/{name}", 1)[0])
            c0, t0 = time.process_time(), time.perf_counter()
            runs[name] = run_tracker(make_tracker(scenario, s, rng), scenario, name=f"ssa_seeds seed {index} {case} "
                                     f"{s.label}", progress=progress, n_progress=4)
            timing.append({"case": case, "seed_index": index, "tracker": name,
                           "seconds": time.perf_counter() - t0, "cpu_seconds": time.process_time() - c0})
        runs[BLIND] = blind_run(scenario)  # the negative control of every check (no measurement ever used)
        labels = {**{name: s.label for name, s in settings.items()}, BLIND: BLIND_LABEL}
        for name, label in labels.items():
            ref_map = runs[ref].map_estimates if name not in (ref, bref) else None
            births = bref is not None and name != bref and (name == BLIND or settings[name].population)
            rows.append(_row(case, index, name, label, scenario, runs[name], config[case], ref_map, ref,
                             runs[bref].map_estimates if births else None, bref or ""))
    return pd.DataFrame(rows, columns=SEED_COLUMNS), pd.DataFrame(timing)


def distribution_table(per_seed: pd.DataFrame) -> pd.DataFrame:
    """Per case, tracker and metric of :data:`METRICS` (and the birth latency maximum and OSPA
    over the catalogue): ``n, mean, se, sd, min, q10, q25, median, q75, q90, max`` over seeds."""
    metrics = [m for m in (*METRICS, "expected_number_end", "birth_latency_max", "ospa_catalogue_mean",
                           "children_per_scan_mean") if m in per_seed]  # (a table without the pair with births)
    rows = []
    for (case, tracker), g in per_seed.groupby(["case", "tracker"], sort=False):
        for m in metrics:
            x = g[m].to_numpy(dtype=float)
            x = x[np.isfinite(x)]
            if not len(x):
                continue
            q = np.quantile(x, [0.1, 0.25, 0.5, 0.75, 0.9])
            sd = float(x.std(ddof=1)) if len(x) > 1 else np.nan
            rows.append({"case": case, "tracker": tracker, "label": g["label"].iloc[0], "metric": m, "n": len(x),
                         "mean": float(x.mean()), "se": sd / np.sqrt(len(x)) if len(x) > 1 else np.nan, "sd": sd,
                         "min": float(x.min()), "q10": q[0], "q25": q[1], "median": q[2], "q75": q[3], "q90": q[4],
                         "max": float(x.max())})
    return pd.DataFrame(rows)


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


def _mc_control(g: pd.DataFrame, col: str, published: float, tol: float) -> tuple[str, bool]:
    """The blind tracker's value of a Monte Carlo test and whether it passes the same rule."""
    x = g[col].to_numpy(dtype=float)
    if len(x) < 2 or not np.isfinite(x).all():
        return "; ".join(f"{v:.4g}" for v in x), False
    c = monte_carlo_claim("control", "control", "control", float(published), x, abs_tol=tol, digits=4)
    return f"mean {float(c.mean):.4g} over {len(x)} seeds ({c.status})", c.status == "reproduced"


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
    ex, claims = "ssa_seeds", []
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
        key = f"{case}_{tracker}_"
        for col, item, source, published, tol, k in _tests(case, g, names[(case, ref)] if ref else "",
                                                           names[(case, bref)] if bref else ""):
            x = g[col].to_numpy(dtype=float)
            if n >= 2 and np.isfinite(x).all():
                c = monte_carlo_claim(ex, f"{case}, {label}: {item}", source, float(published), x,
                                      abs_tol=tol, digits=4, key=key + k,
                                      claim=_claim_id(case, tracker, k, names.get((case, bref), "")),
                                      note=f"over {n} scenario seeds; min {x.min():.4g}, median "
                                           f"{np.median(x):.4g}, max {x.max():.4g}")
            else:
                c = Claim(ex, f"{case}, {label}: {item}", source, f"{published:.4g}",
                          "; ".join(f"{v:.4g}" for v in x), f"+/- {tol:g}", "inconclusive",
                          f"{n} seed(s): too few for a Monte Carlo verdict", "measurement", key=key + k)
            if k == "AgreementBirths":
                c = replace(c, note=f"{c.note}; {names[(case, bref)]}: Reid's factors for the objects and document "
                                    "000 Eq. 30's probabilities for births and deaths (this project's construction)")
            if ctl is not None:
                c = with_control(c, BLIND_LABEL, *_mc_control(ctl, col, published, tol))
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
            c = Claim(ex, f"{case}, {label}: every birth tracked at the end", "000 Sec. IV-A",
                      "all", f"{tracked} of {total} births over {n} seeds", "all",
                      "reproduced" if tracked == total else "not reproduced",
                      f"latency (scans from first in view to a correct MAP track): median "
                      f"{np.nanmedian(g['birth_latency_mean']):.3g}, worst {np.nanmax(g['birth_latency_max']):.3g}",
                      "published number", key=key + "Births", claim=_claim_id(case, tracker, "Births"))
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


_BIRTH_METRICS = ("births_tracked_end", "birth_latency_mean")  #: undefined for a case without births


def plot_distributions(per_seed: pd.DataFrame, *, title: str):
    """One panel per metric of :data:`METRICS`: every seed's value (dots) and the box of the
    quartiles per case and tracker, so the spread over seeds is seen, not only the mean.

    Horizontal boxes, one row per case and tracker (named once, on the left). A birth metric of
    a case without births (ssa15) is not drawn as 0: its row says "n/a (no births)".
    """
    from ...reporting import figure_style

    groups = [(k, g) for k, g in per_seed.groupby(["case", "tracker"], sort=False) if k[1] != BLIND]
    names = [f"{case}: {g['label'].iloc[0]}" for (case, _), g in groups]
    n_rows = -(-len(METRICS) // 2)
    fig, axes = figure_style.subplots(n_rows, 2, height=min(1.6 + 0.32 * n_rows * len(groups),
                                                            figure_style.MAX_HEIGHT_IN), sharey=True)
    for ax in axes.flat[len(METRICS):]:
        ax.set_axis_off()
    for ax, (metric, what) in zip(axes.flat, METRICS.items()):
        data = []
        for _, g in groups:
            x = g[metric].to_numpy(dtype=float)
            if metric in _BIRTH_METRICS and (g["births"].to_numpy() == 0).all():
                x = np.full_like(x, np.nan)
            data.append(x)
        pos = [i for i, x in enumerate(data) if np.isfinite(x).any()]
        if pos:
            ax.boxplot([data[i][np.isfinite(data[i])] for i in pos], positions=pos, widths=0.5, showfliers=False,
                       orientation="horizontal")
        for i in pos:
            x = data[i][np.isfinite(data[i])]
            jitter = np.linspace(-0.12, 0.12, len(x)) if len(x) > 1 else np.zeros(1)
            ax.plot(x, i + jitter, "o", ms=3, alpha=0.7, color="#2c7bb6")
        for i in set(range(len(groups))) - set(pos):
            why = "n/a (no births)" if metric in _BIRTH_METRICS and (groups[i][1]["births"] == 0).all() else "n/a"
            ax.text(0.02, i, why, transform=ax.get_yaxis_transform(), va="center", color="0.4")
        ax.set_yticks(range(len(names)), names)
        ax.set_ylim(len(names) - 0.4, -0.6)
        ax.set_title(textwrap.fill(what, 30))  # a panel is a third of the page wide
        ax.grid(alpha=0.3, axis="x")
    n = per_seed["seed_index"].nunique()
    fig.suptitle(figure_style.wrap(f"{title}\n{n} scenario seeds; boxes: quartiles, whiskers: 1.5 IQR, dots: "
                                   "one seed each", fig))
    return fig
