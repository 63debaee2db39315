"""How far Table 6.1 (document 003) depends on the readings the document leaves open.

* :func:`table61_sensitivity_cells` — Monte Carlo MOSPA of the ideal filter (best pairing and
  labelled), the MHT and the ECMHT for one initial-position variance of ``X₀``, under every scoring
  window (scored scans dropped at the start) and both scored estimates, ``X(k|k−1)`` and ``X(k|k)``;
* :func:`pdaf_variant_cells` — the same for every multi-sensor PDAF form of
  :data:`~hypotrack.trackers.ecmht.PDAF_VARIANTS` (per-sensor sequential, equivalent measurement,
  parallel, all returns at once, JPDA-coupled) and one start (stated or stationary variance);
* :func:`ideal_oracle_monte_carlo` — a large ideal-filter-only Monte Carlo for the rows that check
  the closed form of :mod:`.oracle` (the ideal costs little, so enough runs decide at a tight tolerance);
* :func:`sensitivity_verdicts` — each cell's verdict against the published value by the ledger's one
  Monte Carlo rule (:func:`hypotrack.reporting.verdict.monte_carlo_verdict`);
* :func:`plot_table61_sensitivity`, :func:`plot_pdaf_variants` — the figures.

Every Monte Carlo here runs in chunks of runs, each from its own child stream of the seed, so a
table depends only on the seed, the run count and the chunk size.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..._validation import check_int, check_nonnegative
from ...models.motion import OrnsteinUhlenbeck
from ...reporting.verdict import monte_carlo_verdict
from ...scenarios.closely_spaced import simulate_closely_spaced
from ...trackers.ecmht import PDAF_VARIANTS, ECMHTFilter, GNNFilter, IdealFilter, PDAFilter, mospa_two_targets
from .run import LABELLED_IDEAL, TABLE_6_1

__all__ = ["ESTIMATES", "ideal_oracle_monte_carlo", "joint_cells", "pdaf_variant_cells", "plot_pdaf_variants",
           "plot_table61_sensitivity", "sensitivity_macros", "sensitivity_verdicts", "table61_sensitivity_cells",
           "window_label"]

#: Scored estimate -> its name in the tables: the one-step prediction or the filtered estimate.
ESTIMATES = {"predicted": "X(k|k-1)", "filtered": "X(k|k)"}


def window_label(skip: int, n_scans: int) -> str:
    """The scans a window scores: scoring starts at scan 2, ``skip`` scored scans are dropped."""
    return f"scans {skip + 2} to {n_scans}"


def _chunks(n_runs: int, chunk_runs: int, seed):
    n_runs = check_int(n_runs, "n_runs", minimum=2)
    chunk_runs = check_int(chunk_runs, "chunk_runs", minimum=1)
    sizes = [min(chunk_runs, n_runs - start) for start in range(0, n_runs, chunk_runs)]
    seeds = (np.random.SeedSequence(seed) if isinstance(seed, int) else seed).spawn(len(sizes))
    return zip(sizes, seeds)


def _score(filters: dict, labelled: dict, real) -> dict:
    """Per-run, per-scored-scan squared OSPA ``(n_runs, n_scans − 1)`` of every filter and estimate.

    Keys ``(name, estimate)``; ``labelled`` maps extra names to a filter scored against its own targets.
    """
    n_runs, n_scans = real.truth.shape[:2]
    names = [*filters, *labelled]
    out = {(m, e): np.empty((n_runs, n_scans - 1)) for m in names for e in ESTIMATES}
    for k in range(n_scans):
        for f in filters.values():
            f.step(real.scans[:, k])
        if k == 0:
            continue
        truth = real.truth[:, k]
        for name in names:
            f = filters[labelled.get(name, name)]
            for est, x in (("predicted", f.predictions()), ("filtered", f.estimates())):
                if name in labelled:
                    out[(name, est)][:, k - 1] = 0.5 * ((x - truth) ** 2).sum(axis=1)
                else:
                    out[(name, est)][:, k - 1] = mospa_two_targets(x, truth)
    return out


def _window_rows(per_run: dict, skips, n_scans: int, **fixed) -> list:
    rows = []
    for (name, est), parts in per_run.items():
        s = np.concatenate(parts)
        for skip in skips:
            v = s[:, skip:].mean(axis=1)
            rows.append({**fixed, "method": name, "estimate": ESTIMATES[est], "skip": skip,
                         "window": window_label(skip, n_scans), "n": len(v), "mean": v.mean(),
                         "se": v.std(ddof=1) / np.sqrt(len(v))})
    return rows


def _check_skips(skips, n_scans):
    return [check_int(s, "skips", minimum=0, maximum=n_scans - 2) for s in skips]


def table61_sensitivity_cells(*, sigma2, gamma, n_scans, n_sensors, R, dt, initial_variance, skips, n_runs,
                              chunk_runs, seed) -> pd.DataFrame:
    """MOSPA of the Table 6.1 methods for one initial variance of ``X₀`` under every window and estimate.

    Methods: ``ideal`` (best pairing per scan), :data:`~.run.LABELLED_IDEAL` (each track against its
    own target), ``MHT`` and ``ECMHT`` (:mod:`hypotrack.trackers.ecmht`, Eqs. 6.1–6.11). A window
    drops the first ``skip`` scored scans (scoring starts at scan 2). Returns one row per method ×
    estimate × window: ``initial_variance, method, estimate, skip, window, n, mean, se`` (m²).
    """
    n_scans = check_int(n_scans, "n_scans", minimum=2)
    skips = _check_skips(skips, n_scans)
    v0 = check_nonnegative(initial_variance, "initial_variance")
    model = OrnsteinUhlenbeck(sigma2, gamma)
    per_run: dict = {}
    for size, child in _chunks(n_runs, chunk_runs, seed):
        scen, orders = child.spawn(2)
        real = simulate_closely_spaced(model, n_runs=size, n_scans=n_scans, n_sensors=n_sensors, R=R, dt=dt,
                                       initial_variance=v0, rng=np.random.default_rng(scen))
        filters = {"ideal": IdealFilter(model, R, n_sensors, dt), "MHT": GNNFilter(model, R, n_sensors, dt),
                   "ECMHT": ECMHTFilter(model, R, n_sensors, dt, rng=np.random.default_rng(orders))}
        for key, s in _score(filters, {LABELLED_IDEAL: "ideal"}, real).items():
            per_run.setdefault(key, []).append(s)
    return pd.DataFrame(_window_rows(per_run, skips, n_scans, initial_variance=v0))


def pdaf_variant_cells(*, sigma2, gamma, n_scans, n_sensors, R, dt, initial_variance, start, forms, skips, n_runs,
                       chunk_runs, seed) -> pd.DataFrame:
    """MOSPA of every multi-sensor PDAF form (:class:`~hypotrack.trackers.ecmht.PDAFilter`) for one start.

    ``start`` names the initial variance (e.g. "stated", "stationary"). Returns one row per form ×
    estimate × window: ``start, initial_variance, method (PDAF[<form>]), form, estimate, skip, window,
    n, mean, se`` (m²).
    """
    n_scans = check_int(n_scans, "n_scans", minimum=2)
    skips = _check_skips(skips, n_scans)
    v0 = check_nonnegative(initial_variance, "initial_variance")
    for f in forms:
        if f not in PDAF_VARIANTS:
            raise ValueError(f"forms must be among {PDAF_VARIANTS}, got {f!r}")
    model = OrnsteinUhlenbeck(sigma2, gamma)
    per_run: dict = {}
    for size, child in _chunks(n_runs, chunk_runs, seed):
        real = simulate_closely_spaced(model, n_runs=size, n_scans=n_scans, n_sensors=n_sensors, R=R, dt=dt,
                                       initial_variance=v0, rng=np.random.default_rng(child))
        filters = {f"PDAF[{f}]": PDAFilter(model, R, n_sensors, dt, variant=f) for f in forms}
        for key, s in _score(filters, {}, real).items():
            per_run.setdefault(key, []).append(s)
    df = pd.DataFrame(_window_rows(per_run, skips, n_scans, start=start, initial_variance=v0))
    df.insert(3, "form", df["method"].str.extract(r"PDAF\[(\w+)\]", expand=False))
    return df


def ideal_oracle_monte_carlo(*, sigma2, gamma, n_scans, n_sensors, R, dt, initial_variance, transient_scans,
                             n_runs, chunk_runs, seed) -> pd.DataFrame:
    """The ideal filter alone over many runs, for the closed-form rows (:mod:`.oracle`).

    Rows: ``scoring`` (pairing over all scored scans; labelled after ``transient_scans``) × ``estimate``
    (``X(k|k−1)``, what the closed form is computed for; ``X(k|k)``, the negative control), with
    ``n, mean, se`` (m²).
    """
    n_scans = check_int(n_scans, "n_scans", minimum=2)
    skip = check_int(transient_scans, "transient_scans", minimum=0, maximum=n_scans - 2)
    model = OrnsteinUhlenbeck(sigma2, gamma)
    per_run: dict = {}
    for size, child in _chunks(n_runs, chunk_runs, seed):
        real = simulate_closely_spaced(model, n_runs=size, n_scans=n_scans, n_sensors=n_sensors, R=R, dt=dt,
                                       initial_variance=check_nonnegative(initial_variance, "initial_variance"),
                                       rng=np.random.default_rng(child))
        for key, s in _score({"ideal": IdealFilter(model, R, n_sensors, dt)}, {LABELLED_IDEAL: "ideal"},
                             real).items():
            per_run.setdefault(key, []).append(s[:, skip:] if key[0] == LABELLED_IDEAL else s)
    rows = []
    for (name, est), parts in per_run.items():
        v = np.concatenate(parts).mean(axis=1)
        rows.append({"scoring": "labelled" if name == LABELLED_IDEAL else "pairing", "estimate": ESTIMATES[est],
                     "skip": skip if name == LABELLED_IDEAL else 0, "n": len(v), "mean": v.mean(),
                     "se": v.std(ddof=1) / np.sqrt(len(v))})
    return pd.DataFrame(rows)


def sensitivity_verdicts(cells: pd.DataFrame, *, rel_tol: float, published_runs: int | None) -> pd.DataFrame:
    """``cells`` (``method, n, mean, se``, …) with ``published``, ``relative_difference``, ``z`` and ``verdict``.

    The published value of a method is Table 6.1's (the labelled ideal and the ideal share one;
    ``PDAF[<form>]`` takes the PDAF's); the verdict is the ledger's Monte Carlo rule with tolerance
    ``rel_tol × published`` and the published numbers' own error over ``published_runs`` runs.
    """
    rel_tol = check_nonnegative(rel_tol, "rel_tol")
    base = cells["method"].str.replace(r"\[.*\]$", "", regex=True)
    out = cells.copy()
    out["published"] = base.map(TABLE_6_1).astype(float)
    if out["published"].isna().any():
        bad = sorted(set(cells["method"][out["published"].isna()]))
        raise ValueError(f"method must be a Table 6.1 method or a variant of one, got {bad}")
    out["relative_difference"] = out["mean"] / out["published"] - 1
    verdicts = [monte_carlo_verdict(float(r.mean), float(r.se), float(r.published), rel_tol * float(r.published),
                                    int(r.n), published_runs) for r in out.itertuples()]
    out["z"] = [v.z for v in verdicts]
    out["verdict"] = [v.status for v in verdicts]
    return out


#: Tick labels of the PDAF forms (two lines each, so they never collide at print size).
_FORM_LABELS = {"sequential": "sensor by\nsensor", "equivalent": "equivalent\nmeas.",
                "parallel": "parallel", "all_at_once": "all returns\nat once", "jpda": "JPDA-\ncoupled"}
_MARK = {"reproduced": "o", "inconclusive": "s", "not reproduced": "x"}


def _save(fig, pdf, png) -> None:
    from ...reporting import figure_style

    figure_style.save(fig, pdf, png, width=1.0)  # placed at the full line width; refuses text under 7 pt


def plot_table61_sensitivity(table: pd.DataFrame, pdf, png, *, rel_tol: float) -> None:
    """Three panels (ideal, MHT, ECMHT): MOSPA of ``X(k|k−1)`` per window, one line per initial variance,
    the published value ± ``rel_tol`` shaded; marker = verdict. Sized for a full text width (7 in)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = table[table["estimate"] == ESTIMATES["predicted"]]
    methods = [m for m in ("ideal", LABELLED_IDEAL, "MHT", "ECMHT") if m in set(t["method"])]
    from ...reporting import figure_style as fs

    with plt.rc_context({"font.size": 9}):
        fig, axes = fs.subplots(1, len(methods), height=3.2, sharex=True)
        axes = np.atleast_1d(axes)
        v0s = sorted(t["initial_variance"].unique())
        colours = plt.cm.viridis(np.linspace(0, 0.85, len(v0s)))
        for ax, m in zip(axes, methods):
            d = t[t["method"] == m]
            pub = float(d["published"].iloc[0])
            ax.axhspan(pub * (1 - rel_tol), pub * (1 + rel_tol), color="0.88", lw=0)
            ax.axhline(pub, color="k", lw=0.8, ls="--")
            for v0, c in zip(v0s, colours):
                dv = d[d["initial_variance"] == v0].sort_values("skip")
                ax.plot(dv["skip"] + 2, dv["mean"], "-", color=c, lw=1, label=f"{v0:g} m²")
                for verdict, mk in _MARK.items():
                    sel = dv[dv["verdict"] == verdict]
                    ax.plot(sel["skip"] + 2, sel["mean"], mk, color=c, ms=4, mfc="none" if mk == "o" else c)
            ax.set_title("ideal, labelled" if m == LABELLED_IDEAL else m, fontsize=9)
            ax.set_xlabel("first scored scan")
        axes[0].set_ylabel("MOSPA (m²)")
        handles, labels = axes[0].get_legend_handles_labels()
        handles += [plt.Line2D([], [], ls="", marker=mk, color="k", mfc="none" if mk == "o" else "k")
                    for mk in _MARK.values()]
        labels += list(_MARK)
        fs.legend_below(fig, handles, labels, ncol=7, title="X₀ variance / verdict", fontsize=8, title_fontsize=8,
                        frameon=False)
        _save(fig, pdf, png)


def plot_pdaf_variants(table: pd.DataFrame, pdf, png, *, rel_tol: float) -> None:
    """MOSPA of every PDAF form × start × estimate over all scans, against the published 0.8518 ± ``rel_tol``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = table[table["skip"] == table["skip"].min()].copy()
    t["case"] = t["start"] + ", " + t["estimate"]
    cases = list(dict.fromkeys(t["case"]))
    forms = list(dict.fromkeys(t["form"]))
    from ...reporting import figure_style as fs

    with plt.rc_context({"font.size": 9}):
        fig, ax = fs.subplots(height=3.2)
        pub = float(t["published"].iloc[0])
        ax.axhspan(pub * (1 - rel_tol), pub * (1 + rel_tol), color="0.88", lw=0, label="published ± tolerance")
        width = 0.8 / len(cases)
        for i, case in enumerate(cases):
            d = t[t["case"] == case].set_index("form").reindex(forms)
            ax.bar(np.arange(len(forms)) + (i - (len(cases) - 1) / 2) * width, d["mean"], width,
                   yerr=3 * d["se"], label=case, color=plt.cm.tab10(i))
        ax.set_xticks(np.arange(len(forms)), [_FORM_LABELS.get(f, f) for f in forms])
        ax.set_ylabel("MOSPA (m²), all scans")
        fs.legend_below(fig, *ax.get_legend_handles_labels(), ncol=5, fontsize=8, frameon=False,
                        title="start, scored estimate", title_fontsize=8)
        _save(fig, pdf, png)


def joint_cells(table: pd.DataFrame, methods) -> pd.DataFrame:
    """The readings (initial variance × window × estimate) under which every one of ``methods`` is reproduced."""
    t = table[table["method"].isin(methods)]
    keys = ["initial_variance", "skip", "window", "estimate"]
    ok = t.groupby(keys)["verdict"].agg(lambda v: len(v) == len(methods) and (v == "reproduced").all())
    return ok[ok].reset_index()[keys]


def _cells_text(cells: pd.DataFrame) -> str:
    if cells.empty:
        return "none"
    return "; ".join(f"X₀ variance {r.initial_variance:g} m², {r.window}, {r.estimate}" for r in cells.itertuples())


def sensitivity_macros(table: pd.DataFrame, pdaf: pd.DataFrame, cfg) -> dict:
    """Numbers the paper quotes from the sensitivity tables (names stable, never a config value).

    Per method (``Ideal``, ``IdealLabelled``, ``Mht``, ``Ecmht``), over every reading scored on
    ``X(k|k−1)``: ``Sens<M>Min``, ``Sens<M>Max`` and ``Sens<M>Reproduced`` (cells reproduced, of
    ``SensCells``); the readings reproducing ideal, MHT and ECMHT at once (``SensJoint``, with the
    pairing ideal; ``SensJointLabelled``, with the labelled ideal); the PDAF readings' range and count.
    """
    t = table[table["estimate"] == ESTIMATES["predicted"]]
    out = {"SensCells": str(int((t["method"] == "MHT").sum())), "SensRuns": str(int(t["n"].iloc[0])),
           "SensVariances": ", ".join(f"{v:g}" for v in sorted(t["initial_variance"].unique())),
           "SensWindows": ", ".join(dict.fromkeys(t.sort_values("skip")["window"]))}
    for name, m in (("Ideal", "ideal"), ("IdealLabelled", LABELLED_IDEAL), ("Mht", "MHT"), ("Ecmht", "ECMHT")):
        d = t[t["method"] == m]
        out[f"Sens{name}Min"] = f"{d['mean'].min():.4g}"
        out[f"Sens{name}Max"] = f"{d['mean'].max():.4g}"
        out[f"Sens{name}Reproduced"] = str(int((d["verdict"] == "reproduced").sum()))
    out["SensJoint"] = _cells_text(joint_cells(table, ["ideal", "MHT", "ECMHT"]))
    out["SensJointLabelled"] = _cells_text(joint_cells(table, [LABELLED_IDEAL, "MHT", "ECMHT"]))
    whole = pdaf[pdaf["skip"] == pdaf["skip"].min()]
    out["PdafReadings"] = str(len(whole))
    out["PdafMin"] = f"{whole['mean'].min():.3g}"
    out["PdafMax"] = f"{whole['mean'].max():.3g}"
    out["PdafMaxShortfall"] = f"{100 * (1 - whole['mean'].max() / TABLE_6_1['PDAF']):.0f}"
    out["PdafReproduced"] = str(int((pdaf["verdict"] == "reproduced").sum()))
    return out
