"""Every report figure is legible at the size it is printed: no text under 7 pt at its placed width,
no title cut by the figure's edge, no legend over an axes' data area.

The checker (:func:`figure_style.legibility_problems`) is tested on figures built to fail each rule
(its negative controls); the figure functions are then drawn on small fabricated tables and must
pass it at the width their ``\\htfigure`` line in paper/sections places them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from hypotrack.reporting import figure_style as fs

fs.use()
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parents[3]


def placed_widths() -> dict[str, float]:
    """``\\htfigure`` placements in the report: figure path (under generated/figures/) -> line-width fraction."""
    out = {}
    for tex in sorted((ROOT / "paper" / "sections").rglob("*.tex")):
        for m in re.finditer(r"\\htfigure\{generated/figures/([^}]+)\}\{([0-9.]+)\}", tex.read_text()):
            out[m.group(1)] = float(m.group(2))
    return out


# --- the checker and its negative controls ---------------------------------------------------------


def test_page_geometry_matches_ms_tex():
    # a4paper (210 × 297 mm) with margin=2.2cm: 166 mm = 6.535 in wide, 253 mm tall
    text = (ROOT / "paper" / "ms.tex").read_text()
    assert "a4paper" in text and "margin=2.2cm" in text and "height=0.7\\textheight" in text
    assert fs.TEXT_WIDTH_IN == pytest.approx(166 / 25.4)
    assert fs.MAX_HEIGHT_IN == pytest.approx(0.7 * 253 / 25.4)


def test_good_figure_passes_and_scale_is_exact():
    fig, ax = fs.subplots(height=3.0)
    ax.plot([0, 1], [0, 1], label="a line")
    ax.set_title("a title")
    fs.legend_below(fig)
    assert fs.placed_scale(fig, 1.0) == pytest.approx(1.0)
    assert fs.placed_scale(fig, 0.5) == pytest.approx(0.5)
    assert fs.legibility_problems(fig) == []
    plt.close(fig)


def test_control_figure_drawn_too_wide_has_small_text():
    # a 13 in figure with 8 pt text placed at 6.535 in: 8 × 6.535 / 13 = 4.02 pt
    fig, ax = plt.subplots(figsize=(13, 4))
    ax.set_xlabel("x", fontsize=8)
    problems = fs.legibility_problems(fig, 1.0)
    assert any("4.0 pt" in p for p in problems), problems
    plt.close(fig)


def test_control_too_tall_figure_is_scaled_by_its_height():
    # 10 in tall, 6.535 in wide: LaTeX caps it at 6.97 in, so 8 pt prints at 8 × 6.97 / 10 = 5.6 pt
    fig, ax = plt.subplots(figsize=(fs.TEXT_WIDTH_IN, 10))
    ax.set_xlabel("x", fontsize=8)
    assert fs.placed_scale(fig) == pytest.approx(fs.MAX_HEIGHT_IN / 10)
    assert any("5.6 pt" in p for p in fs.legibility_problems(fig)), fs.legibility_problems(fig)
    plt.close(fig)


def test_control_legend_inside_axes_and_clipped_title_are_found():
    fig, ax = fs.subplots(height=3.0)
    ax.plot(np.arange(10), np.arange(10), label="data")
    ax.legend(loc="center")
    fig.suptitle("a title far too long for the page " * 8)
    problems = fs.legibility_problems(fig)
    assert any("legend" in p and "covers" in p for p in problems), problems
    assert any("cut by the figure's edge" in p for p in problems), problems
    with pytest.raises(ValueError, match="not legible"):
        fs.save(fig, "/nonexistent/never_written.pdf")


def test_control_tiny_subscript_is_measured_per_glyph():
    # 8 pt text at full width: P is 8 pt (passes 7 pt), D is 0.7 × 8 = 5.6 pt, x_2 inside a
    # superscript is 0.49 × 8 = 3.92 pt: the check reports the smallest glyph
    fig, ax = fs.subplots(height=3.0)
    ax.set_xlabel("probability of detection $P_D$", fontsize=8)
    assert fs.text_sizes(ax.xaxis.label) == (8.0, pytest.approx(5.6))
    assert any("5.6 pt" in p and "sub- or superscript" in p for p in fs.legibility_problems(fig)), \
        fs.legibility_problems(fig)
    ax.set_xlabel("$a^{x_2}$", fontsize=8)
    assert fs.text_sizes(ax.xaxis.label)[1] == pytest.approx(3.92)
    # placed at half width, 8.6 pt text with a script prints its script at 8.6 × 0.7 × 0.5 = 3.0 pt
    ax.set_xlabel("$P_D$", fontsize=8.6)
    assert any("3.0 pt" in p for p in fs.legibility_problems(fig, 0.5)), fs.legibility_problems(fig, 0.5)
    # plain text is one size, and 8.58 pt with a script passes at full width (8.58 × 0.7 = 6.006)
    ax.set_xlabel("plain words", fontsize=8)
    assert fs.text_sizes(ax.xaxis.label) == (8.0, 8.0)
    ax.set_xlabel("$P_D$", fontsize=8.58)
    assert fs.legibility_problems(fig) == []
    plt.close(fig)


def test_control_log_axis_exponents_are_enlarged_by_save(tmp_path):
    # a log axis labels its ticks $10^{k}$: the exponent at 7.5 × 0.7 = 5.25 pt fails ...
    fig, ax = fs.subplots(height=3.0)
    ax.semilogy([1, 2, 3], [1e-3, 1.0, 1e3])
    problems = fs.legibility_problems(fig)
    assert any("5.2 pt" in p and "10^{" in p for p in problems), problems
    # ... and is raised to 6 / 0.7 = 8.58 pt, so save writes the figure
    fs.enlarge_scripts(fig)
    assert ax.yaxis.get_major_ticks()[0].label1.get_fontsize() == pytest.approx(8.58)
    assert fs.legibility_problems(fig) == []
    fs.save(fig, tmp_path / "log.pdf")
    assert (tmp_path / "log.pdf").stat().st_size > 0


def test_control_series_of_the_same_look_are_found():
    fig, (a1, a2) = fs.subplots(1, 2, height=3.0)
    a1.plot([0, 1, 2], [0, 1, 4], "o-", color="tab:blue", label="tracker A")
    a1.plot([0, 1, 2], [1, 2, 3], "o-", color="tab:blue", label="tracker B")
    problems = fs.legibility_problems(fig)
    assert any("'tracker A' and 'tracker B'" in p and "same colour" in p for p in problems), problems
    # a different marker (or line style, or colour) tells them apart
    a1.lines[1].set_marker("s")
    assert fs.series_problems(fig) == []
    # two panels whose series share a style are fine until one legend lists both with different labels
    a2.plot([0, 1, 2], [5, 5, 5], "o-", color="tab:blue", label="tracker C")
    assert fs.series_problems(fig) == []
    fs.legend_below(fig)
    problems = fs.legibility_problems(fig)
    assert any("legend entries 'tracker A' and 'tracker C'" in p for p in problems), problems
    plt.close(fig)


def test_control_coincident_series_need_a_note():
    fig, ax = fs.subplots(height=3.0)
    x = np.arange(20.0)
    ax.plot(x, x**2, color="tab:blue", lw=2, label="chain")
    ax.plot(x, x**2, color="tab:red", ls="--", label="completion")
    problems = fs.legibility_problems(fig)
    assert len(problems) == 1 and "'completion' lies exactly on 'chain'" in problems[0], problems
    # a series on a subset of another's points is hidden at every point too
    ax.lines[1].set_data(x[5:12], x[5:12] ** 2)
    assert any("lies exactly on" in p for p in fs.series_problems(fig))
    # one point off the other line: not coincident
    ax.lines[1].set_data(x[5:12], x[5:12] ** 2 + (x[5:12] == 8))
    assert fs.series_problems(fig) == []
    # identical data said in the legend passes
    ax.lines[1].set_data(x, x**2)
    ax.lines[1].set_label("completion (coincides with chain)")
    assert fs.legibility_problems(fig) == []
    plt.close(fig)


def test_text_only_legend_rows_are_not_series():
    fig, ax = fs.subplots(height=3.0)
    ax.plot([0, 1], [0, 1], label="data")
    fs.legend_below(fig)
    handles = [plt.Line2D([], [], ls="none", label=f"note {i}") for i in range(3)]
    fig.legends[0].remove()
    fs.legend_below(fig, [ax.lines[0], *handles], ["data"] + [h.get_label() for h in handles])
    assert fs.legibility_problems(fig) == []
    plt.close(fig)


def test_subplots_rejects_sizes_latex_would_shrink():
    with pytest.raises(ValueError, match="height must be"):
        fs.subplots(height=9.0)
    with pytest.raises(ValueError, match="width must be"):
        fs.subplots(width=1.2, height=3.0)


def test_pow10_and_wrap():
    assert fs.pow10(6) == "10⁶" and fs.pow10(-3) == "10⁻³" and fs.pow10(33.0) == "10³³"
    fig, _ = fs.subplots(height=2.0)
    lines = fs.wrap("word " * 100, fig, 9.0).split("\n")
    assert len(lines) > 1 and max(map(len, lines)) <= int(0.95 * fs.TEXT_WIDTH_IN * 72 / 5.4)
    plt.close(fig)


# --- the figure functions on fabricated tables ------------------------------------------------------


def check(fig, name):
    """Legible at the width the report places ``name`` at (its ``\\htfigure`` line), after the
    script enlargement :func:`figure_style.save` applies before it writes a figure."""
    width = placed_widths()[name]
    fs.enlarge_scripts(fig, width)
    problems = fs.legibility_problems(fig, width)
    plt.close(fig)
    assert problems == [], problems


def _save_and_check(monkeypatch, name):
    """Capture the figure a plotting function hands to figure_style.save and check it."""
    seen = []

    def fake_save(fig, pdf, png=None, *, width=1.0, dpi=150):
        seen.append((fig, width))

    monkeypatch.setattr(fs, "save", fake_save)
    return seen


def test_placements_are_full_width_for_the_split_figures():
    widths = placed_widths()
    for name in ("generation_time/difficulty", "generation_time/difficulty_map", "generation_time/difficulty_truth",
                 "samplers/mass_vs_budget", "ssa15/fig_12_14_estimates", "generation_time/generation_time"):
        assert widths[name] == 1.0, name


def test_ssa_figures(monkeypatch):
    from hypotrack.experiments.ssa import figures as sf
    from hypotrack.experiments.ssa.evaluation import OSPASettings
    from hypotrack.models.sensors import FieldOfView

    rng = np.random.default_rng(3)
    n_scans = 20
    weights = pd.DataFrame([dict(scan=k, rank=r + 1, weight=w, n_objects=10 + r % 3, time=600.0 * k)
                            for k in (2, 10, 15, 19) for r, w in enumerate(np.sort(rng.dirichlet(np.ones(20)))[::-1])])
    check(sf.plot_weight_snapshots(weights, n_scans, title="Hypothesis weights during the run (R-FISST; 50 objects: "
                                   "45 in the initial hypothesis, 5 births)"), "ssa50/fig_6_weights")
    rows = []
    for tracker in ("rfisst_chain", "homht"):
        for k in (0, 10, 19):
            for i in range(15):
                ang = rng.uniform(0, 2 * np.pi)
                x, y = 26000 * np.cos(ang), 26000 * np.sin(ang)
                rows.append(dict(scan=k, tracker=tracker, role="truth", status="correct" if i else "missed", x=x,
                                 y=y, id=i))
                rows.append(dict(scan=k, tracker=tracker, role="estimate", status="correct" if i > 1 else "incorrect",
                                 x=x + 10, y=y, id=i))
    matched = pd.DataFrame(rows)
    fov = FieldOfView()
    fig = sf.plot_estimate_snapshots(matched, fov, n_scans, columns=["rfisst_chain", "homht"],
                                     column_titles=["R-FISST, paper chain", "HOMHT"],
                                     title="True positions and MAP estimates (15 objects, all known and starting "
                                     "in view; same EKF)")
    check(fig, "ssa15/fig_12_14_estimates")
    one = matched[matched.tracker == "homht"].drop(columns="tracker")
    check(sf.plot_estimate_snapshots(one, fov, n_scans, column_titles=["R-FISST, top hypothesis"], birth_ids=[3],
                                     title="True positions and top-hypothesis estimates (R-FISST; 50 objects: 45 in "
                                     "the initial hypothesis, 5 births)"), "ssa50/fig_8_10_estimates")
    metrics = pd.DataFrame(dict(scan=np.arange(n_scans), time=600.0 * np.arange(n_scans),
                                expected_number=45 + np.arange(n_scans) / 4, n_catalogue=45 + np.arange(n_scans) // 4,
                                ospa_in_view=rng.uniform(0, 5, n_scans), ospa_catalogue=rng.uniform(0, 50, n_scans)))
    card = pd.DataFrame([dict(scan=k, n_objects=45 + k // 4, probability=1.0) for k in range(n_scans)])
    check(sf.plot_expected_number(metrics, card, title="Expected number of objects (R-FISST; 50 objects: 45 in the "
                                  "initial hypothesis, 5 births)"), "ssa50/fig_11_expected_number")
    ospa = OSPASettings(p=2.0, c_in_view=10.0, c_catalogue=100.0)
    # the ssa15 trackers' labels (TrackerSettings.label), the longest first
    labels = {"rfisst_fixed": "R-FISST + completion, fixed number", "rfisst_chain": "R-FISST, paper chain",
              "rfisst": "R-FISST + completion", "homht": "HOMHT"}
    all_metrics = pd.concat([metrics.assign(tracker=t) for t in labels], ignore_index=True)
    check(sf.plot_ospa(all_metrics, ospa, title="OSPA of the top-hypothesis estimates (50 objects, 5 births)",
                       labels=labels), "ssa50/ospa")
    agreement = pd.DataFrame(dict(agree=np.arange(n_scans) % 7 != 0, same_objects=np.arange(n_scans) % 9 != 0,
                                  max_difference_km=rng.uniform(0, 1e-3, n_scans)))
    agreements = {("rfisst_chain", "homht"): agreement, ("rfisst", "homht"): agreement,
                  ("rfisst_fixed", "homht"): agreement}
    check(sf.plot_comparison(agreements, all_metrics, ospa, labels=labels,
                             title="R-FISST, paper chain vs HOMHT (15 objects, all known; same EKF)"), "ssa15/comparison")


def test_generation_time_figures(monkeypatch):
    from hypotrack.experiments.generation_time import figures as gf

    seen = _save_and_check(monkeypatch, "generation_time")
    rows = []
    for method in ("homht", "rfisst", "homht_kbest"):
        for n in range(2, 30, 2):
            rows.append(dict(method=method, n_objects=n, n_returns=n, log10_hypotheses=4.0 * n,
                             seconds=(1e-3 * n * {"homht": 1.0, "rfisst": 0.3, "homht_kbest": 3.0}[method]
                                      if method != "homht" or n < 10 else np.nan),
                             truth_found=not (method == "rfisst" and n > 24)))
    gf.plot_generation_time(pd.DataFrame(rows), "x.pdf", "x.png", budget=1e7, mcmc_steps=10000, keep=100)
    fig, width = seen.pop()
    check(fig, "generation_time/generation_time")
    summary = pd.DataFrame([dict(difficulty=d, method=m, log10_hypotheses=float(n), mass_captured_mean=0.9,
                                 map_found_rate=0.8, truth_found_rate=0.7)
                            for d in ("paper", "8sigma", "4sigma", "2sigma", "1sigma")
                            for m in ("murty", "chain_completion", "chain") for n in range(2, 40, 6)])
    labels = {"paper": "paper-style problem", "8sigma": "8 σ apart", "4sigma": "4 σ apart", "2sigma": "2 σ apart",
              "1sigma": "1 σ apart"}
    for measure, name in (("mass", "difficulty"), ("map", "difficulty_map"), ("truth", "difficulty_truth")):
        gf.plot_difficulty(summary, "x.pdf", "x.png", labels=labels, mcmc_steps=10000, keep=100, reference_k=1000,
                           exhaustive_max_events=10**6, measure=measure)
        fig, width = seen.pop()
        check(fig, f"generation_time/{name}")
    with pytest.raises(ValueError, match="measure must be one of"):
        gf.plot_difficulty(summary, "x.pdf", "x.png", labels=labels, mcmc_steps=1, keep=1, reference_k=1,
                           exhaustive_max_events=1, measure="speed")
    table = pd.DataFrame(dict(label=[f"engine path {i}" for i in range(6)], per_second=10.0 ** np.arange(5, 11),
                              target_per_second=[1e6, np.nan, 1e7, np.nan, 1e8, np.nan]))
    gf.plot_throughput(table, "x.pdf", "x.png")
    fig, width = seen.pop()
    check(fig, "perf/hypotheses_throughput")


def test_sampler_mass_figure(monkeypatch):
    from hypotrack.experiments.samplers import summary as ss

    seen = _save_and_check(monkeypatch, "samplers")
    diffs = ["1sigma", "2sigma", "4sigma", "8sigma", "recorded"]
    samplers = ["rfisst_chain", "rfisst_completion", "gibbs", "murty"]
    budgets = [10, 100, 1000]
    det = pd.DataFrame([dict(difficulty=d, sampler=s, budget=b, mass_mean=1 - 10.0 ** -(i + j), mass_exact=True,
                             n_problems=8) for d in diffs for i, s in enumerate(samplers)
                        for j, b in enumerate(budgets)])
    timing = det[["difficulty", "sampler", "budget"]].assign(time_mean_s=det.budget * 1e-4)
    ss.plot_mass(det, timing, "x.pdf", "x.png")
    fig, width = seen.pop()
    check(fig, "samplers/mass_vs_budget")


def test_seed_distributions_figure_says_na_for_births_of_a_case_without_births():
    from hypotrack.experiments.ssa_seeds.figures import plot_distributions
    from hypotrack.experiments.ssa_seeds.run import METRICS

    rows = []
    for case, trackers, births in (("ssa50", ["rfisst_chain", "rfisst", "glmb"], 5),
                                   ("ssa15", ["rfisst_chain", "rfisst", "homht", "rfisst_fixed"], 0)):
        for t in trackers:
            for s in range(4):
                rows.append(dict(case=case, tracker=t, label=f"{t} label", seed_index=s, births=births,
                                 **{m: (0.0 if births == 0 and "birth" in m else 0.5 + 0.1 * s) for m in METRICS}))
    fig = plot_distributions(pd.DataFrame(rows), title="SSA verdicts over scenario seeds (document 000 Sec. IV-A)")
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    # ssa15 has 4 trackers and no births: both birth panels say n/a for each, no other panel does
    assert texts.count("n/a (no births)") == 2 * 4 and len(texts) == 8
    births_ax = fig.axes[list(METRICS).index("births_tracked_end")]
    drawn = np.concatenate([line.get_ydata() for line in births_ax.lines if line.get_marker() == "o"])
    assert drawn.max() < 3  # only the three ssa50 rows (0, 1, 2) carry dots
    check(fig, "ssa_seeds/distributions")


def test_scenario_figure_lists_births_in_its_legend():
    from hypotrack.experiments.ssa.scenario_figures import plot_scenario
    from hypotrack.scenarios.ssa import SSAParams, simulate_ssa

    small = simulate_ssa(SSAParams(n_scans=60), 9)
    fig = plot_scenario(small.truth, small.scans, small.fov, small.prior_ids)
    legend_texts = [t.get_text() for t in fig.legends[0].get_texts()]
    assert sum(t.startswith("birth id ") for t in legend_texts) == 5  # the five births of SSAParams
    assert all(ax.get_legend() is None for ax in fig.axes)  # nothing drawn over the orbits
    check(fig, "ssa/ssa50_scenario")


def test_cardinality_figure_tells_tetris_from_count_dp():
    from hypotrack.experiments.cardinality.figures import plot_realisation

    k = np.arange(50)
    counts = pd.DataFrame(dict(scan=k, r=k % 5, n_true=np.full(50, 3), cardinality_tracker=np.full(50, 2),
                               exact_class_map=np.full(50, 2), classical_mht=np.zeros(50, int)))
    cfg = dict(n_scans=50, p_chi=0.9, lambda_b=0.1, lambda_fa=1.0, p_d=0.8)
    fig = plot_realisation(counts, cfg)
    ax = fig.axes[0]
    by_label = {line.get_label(): line for line in ax.lines}
    tetris = next(v for lab, v in by_label.items() if "Tetris" in lab)
    dp = next(v for lab, v in by_label.items() if "count DP" in lab)
    # identical data, yet distinguishable: different line style, marker and width
    assert tetris.get_linestyle() != dp.get_linestyle()
    assert tetris.get_marker() != dp.get_marker()
    assert tetris.get_linewidth() > 2 * dp.get_linewidth() or dp.get_linestyle() == "None"
    check(fig, "cardinality/fig_4_2")


def test_belief_space_figures(monkeypatch):
    from hypotrack.experiments.belief_space import figures as br

    seen = _save_and_check(monkeypatch, "belief_space")
    alpha = np.logspace(-4, -1, 8)  # up to 0.1, where the birth models part
    ratio = pd.concat([pd.DataFrame(dict(p_D=p, alpha=alpha, eq39=(1 - p) * alpha, engine_poisson_limit=(1 - p) * alpha,
                                         engine_binomial=(1 - p) * alpha / (1 - alpha), exact_binomial=(1 - p) * alpha
                                         / (1 - alpha), single_event=(1 - p) * alpha / (1 - 3 * alpha),
                                         engine_single_event=(1 - p) * alpha / (1 - 3 * alpha)))
                       for p in (0.5, 0.9)], ignore_index=True)
    br.plot_ratio(ratio, ["x.pdf", "x.png"], dict(n_pixels=3))
    fig, _ = seen.pop()
    check(fig, "belief_space/undetected_birth_ratio")
    off = np.linspace(-0.5, 0.5, 11)
    offsets = pd.DataFrame(dict(offset_pixels=off, uniform_formula=1 - off**2, gaussian_formula=1 - off**2 / 2,
                                engine=1 - off**2 / 2))
    x = np.logspace(-3, 1, 9)
    noise = pd.DataFrame(dict(spread_over_pixel_area=x, uniform_formula=np.minimum(1.0, 1 / x),
                              variance_matched_analytic=1.8 / (1 + x), gaussian_formula=1.8 / (1 + 1.1 * x),
                              engine=1.8 / (1 + 1.1 * x)))
    br.plot_eq43(offsets, noise, ["x.pdf", "x.png"], dict(pixel_size=10.0, measurement_std=1.0))
    fig, _ = seen.pop()
    check(fig, "belief_space/eq43_bound")
    equiv = pd.DataFrame([dict(run=r, scan=k, max_abs_dlogw_fisst_reid=1e-15, tv_hfisst_reid=0.01 * k)
                          for r in range(3) for k in range(6)])
    br.plot_equivalence(equiv, ["x.pdf", "x.png"])
    fig, width = seen.pop()
    assert width == placed_widths()["belief_space/fisst_vs_homht"] == 0.7
    check(fig, "belief_space/fisst_vs_homht")


def test_coraluppi_and_benchmark_figures(monkeypatch):
    from hypotrack.experiments.closely_spaced import figures as cf
    from hypotrack.experiments.glmb_benchmark import summary as gs
    from hypotrack.experiments.perf_sht import figures as pf
    from hypotrack.experiments.perf_sht import run as ps
    from hypotrack.experiments.swaps import figures as sw

    seen = _save_and_check(monkeypatch, "coraluppi")
    swaps = np.arange(11)
    curves = pd.DataFrame(dict(distance=0.0, swaps=swaps, rms=(swaps - 4.0) ** 2 + 1, log_prob_single=-swaps * 1.0,
                               log_prob_class=-(swaps - 4.0) ** 2, n_runs=500))
    rates = pd.DataFrame(dict(distance=[0.0, 5.0, 10.0], rms_optimal_rate=[0.5, 0.2, 0.0],
                              class_optimal_rate=[0.5, 0.1, 0.0]))
    sw.plot_swap_figures(curves, rates, distance=0.0, n_sensors=10, sigma=1.0,
                         paths={k: (f"{k}.pdf", f"{k}.png") for k in ("fig51", "fig52", "fig53")})
    for name in ("swaps/fig_5_3", "swaps/fig_5_2", "swaps/fig_5_1"):
        fig, width = seen.pop()
        assert width == 0.6
        check(fig, name)
    t = np.arange(50.0)
    offsets = {"truth": 0.0, "MHT": 0.3, "PDAF": 0.6, "ECMHT": 0.15}  # the trackers' tracks apart from the truth
    table = pd.DataFrame(dict(time=t, **{f"{m}_{j}": np.sin(t / 10) + j + (1 - 2 * j) * o for m, o in offsets.items()
                                         for j in range(2)}))
    cf.plot_realisation(table, dict(n_sensors=5, pdaf_variant="joint"),
                        {"fig61": ("a.pdf", "a.png"), "fig62": ("b.pdf", "b.png")})
    for name in ("closely_spaced/fig_6_2", "closely_spaced/fig_6_1"):
        fig, _ = seen.pop()
        check(fig, name)
    curve = pd.concat([pd.DataFrame(dict(tracker=tr, scan=np.arange(30), ospa=50.0 + i, ospa_loc=20.0 + i,
                                         ospa_card=30.0 + i, n_est_mean=5.0 - 0.2 * i, n_est_std=0.5, n_true=5))
                       for i, tr in enumerate(("glmb_gibbs", "glmb_murty", "rfisst", "homht_kbest"))],
                      ignore_index=True)
    gs.plot_benchmark(curve, "x.pdf", "x.png", {"glmb_gibbs": "δ-GLMB, Gibbs sampler (joint prediction-update)"})
    fig, _ = seen.pop()
    check(fig, "glmb_benchmark/ospa_cardinality")
    from hypotrack.experiments.williams2015 import summary as ws

    trackers = ["glmb", "glmb_murty", "homht_kbest", "rfisst", "pmbm_murty", "pmbm_gibbs", "pmb_lbp", "jpda", "gnn"]
    rows = [dict(tracker=t, scan=k, **{c: v * (1 + 0.1 * i) + 0.01 * k for c, v in
                                        (("rms_gospa", 3.0), ("rms_gospa_loc", 1.5), ("rms_gospa_missed", 2.0))},
                 rms_gospa_false=0.0 if t.startswith("pmb") else 1.0 + 0.1 * i)  # the PMBM kinds coincide at 0
            for i, t in enumerate(trackers) for k in range(1, 82)]
    ws.plot_gospa(pd.DataFrame(rows), "x.pdf", "x.png", 10.0, 20)
    fig, _ = seen.pop()
    assert "same curve: pmb_lbp = pmbm_gibbs = pmbm_murty" in fig.axes[3].get_title().replace("\n", " ")
    check(fig, "williams2015/gospa_over_time")
    timings = pd.DataFrame([dict(algorithm=a, clutter_rate=r, implementation=i, n_targets=n, median_ms=0.1 * n * f)
                            for a, rs in (("gnn", [10.0]), ("jpda", [1.0, 10.0, 50.0])) for r in rs
                            for i, f in (("hypotrack", 1.0), ("stonesoup", 30.0), (ps.BASELINE, 2.0))
                            for n in (2, 4, 8, 16)])
    ratios = pd.DataFrame([dict(algorithm=a, peer=p, clutter_rate=10.0, n_targets=n, speedup=f * n,
                                goal=10.0 if a == "gnn" else 100.0)
                           for a, p, f in (("gnn", "Stone Soup", 3.0), ("gnn", "baseline", 0.5),
                                           ("jpda", "Stone Soup", 30.0), ("jpda", "baseline", 1.5))
                           for n in (2, 4, 8, 16)])
    pf.plot_benchmark(timings, ratios, "x.pdf", "x.png")
    fig, _ = seen.pop()
    ax = fig.axes[-1 - sum(not a.get_visible() for a in fig.axes)]
    assert all(t.get_text() == "" or "goal" not in t.get_text() for t in ax.texts)  # goals named in the legend
    check(fig, "perf/sht_timings")


def test_legend_below_drops_columns_until_it_fits():
    fig, ax = fs.subplots(height=3.0)
    for i in range(4):
        ax.plot([0, 1], [i, i], label=f"tracker {i} with a label as long as a GM-PHD peer implementation's")
    leg = fs.legend_below(fig, ncol=3)
    assert leg._ncols == 1  # three or two columns of these labels are wider than 6.5 in
    assert fs.legibility_problems(fig) == []
    plt.close(fig)


def test_sht_figures(monkeypatch):
    from hypotrack.experiments.sht import figures as sf
    from hypotrack.experiments.sht import run as sr

    seen = _save_and_check(monkeypatch, "sht")
    cfg = dict(scenario=dict(n_targets=2, speed=10.0, dt=1.0, n_scans=60, crossing_angle_deg=10.0, sigma=5.0,
                             clutter_rate=10.0, p_D=0.9), ospa=dict(c=50.0, p=2.0), loss_distance=25.0)
    x = np.linspace(-150, 150, 31)
    rows = [dict(kind="truth", id=j, x=xx, y=(1 - 2 * j) * 0.09 * xx, method="") for j in range(2) for xx in x]
    rows += [dict(kind="track", id=j, x=xx, y=(1 - 2 * j) * 0.09 * xx + 2, method=m) for m in sr.METHODS
             for j in range(3) for xx in x]
    rows += [dict(kind=k, id=-1, x=xx, y=y, method="") for k, y in (("clutter", 20.0), ("target_return", 10.0))
             for xx in x]
    t = np.arange(60.0)
    curves = pd.concat([pd.DataFrame(dict(method=m, time=t, separation=np.abs(t - 30) + 5.0 * (i + 1),
                                          separation_se=1.0, truth_separation=np.abs(t - 30), mospa=5.0 + i,
                                          mospa_se=1.0, mospa_targets=4.0 - i, mospa_targets_se=1.0, n_runs=6))
                        for i, m in enumerate(sr.METHODS)], ignore_index=True)
    sf.plot_crossing(pd.DataFrame(rows), curves, cfg, "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "sht/crossing_coalescence")
    table = pd.DataFrame([dict(method=m, clutter_rate=r, mospa=5.0 + r + i, mospa_se=1.0, mospa_targets=4.0 + i,
                               mospa_targets_se=1.0, mean_tracks=2 + r / 10 + i, track_loss=0.1 + 0.1 * i,
                               track_loss_se=0.05, n_runs=4)
                          for i, m in enumerate(sr.METHODS) for r in (0.0, 10.0, 40.0)])
    sf.plot_sweep(table, cfg, "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "sht/clutter_sweep")


def test_closely_spaced_mospa_figure(monkeypatch):
    from hypotrack.experiments.closely_spaced import figures as cf
    from hypotrack.experiments.closely_spaced.run import LABELLED_IDEAL

    seen = _save_and_check(monkeypatch, "closely_spaced")
    cfg = dict(sigma2=0.01, gamma=0.005, initial_variance=0.01, n_sensors=10, R=1.0, dt=1.0, n_scans=100,
               pdaf_variant="sequential")
    t = np.arange(1.0, 100.0)
    methods = ["ideal", LABELLED_IDEAL, "PDAF", "MHT", "ECMHT", "PDAF[equivalent]", "PDAF[parallel]"]
    curves = pd.concat([pd.DataFrame(dict(method=m, time=t, mospa=0.03 * (i + 1))) for i, m in enumerate(methods)],
                       ignore_index=True)
    table = pd.DataFrame(dict(method=["ideal", "PDAF", "MHT", "ECMHT"], published=[0.0363, 0.8518, 0.1376, 0.0586],
                              n=100))
    cf.plot_mospa_vs_scan(curves, table, cfg, "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "closely_spaced/mospa_vs_scan")


def test_every_placed_figure_is_checked_here():
    # the theory notebooks draw their own figures (theory/*.py); every other placed figure is drawn above
    source = Path(__file__).read_text()
    unchecked = [name for name in placed_widths() if f'"{name}"' not in source and not name.startswith("theory/")]
    assert unchecked == []


def test_closely_spaced_sensitivity_figures(monkeypatch):
    from hypotrack.experiments.closely_spaced import sensitivity as cs

    seen = _save_and_check(monkeypatch, "closely_spaced")
    rows = [dict(method=m, initial_variance=v, skip=k, window=f"from scan {k + 2}", estimate=e,
                 mean=0.05 + 0.01 * k + 0.004 * np.log10(v) + (0.002 if e == "X(k|k)" else 0.0),
                 se=0.001, n=100, published=p, verdict=verdict)
            for m, p in (("ideal", 0.0363), ("MHT", 0.1376), ("ECMHT", 0.0586))
            for v in (0.01, 0.1, 1.0, 10.0) for k in (0, 10, 50, 90)
            for e in (cs.ESTIMATES["predicted"], "X(k|k)")
            for verdict in ["reproduced" if k == 0 else "not reproduced"]]
    cs.plot_table61_sensitivity(pd.DataFrame(rows), "x.pdf", "x.png", rel_tol=0.1)
    fig, _ = seen.pop()
    check(fig, "closely_spaced/sensitivity_table_6_1")
    pdaf = pd.DataFrame([dict(form=f, start=s, estimate=e, skip=0, mean=0.2, se=0.01, published=0.8518)
                         for f in ("sequential", "equivalent", "parallel", "all_at_once", "jpda")
                         for s in ("stated", "stationary") for e in ("X(k|k-1)", "X(k|k)")])
    cs.plot_pdaf_variants(pdaf, "x.pdf", "x.png", rel_tol=0.1)
    fig, _ = seen.pop()
    check(fig, "closely_spaced/sensitivity_pdaf")


def test_ssa_catalogue_figures(monkeypatch):
    import yaml

    from hypotrack.experiments.ssa_catalogue import figures as sf
    from hypotrack.experiments.ssa_catalogue.run import make_radar

    seen = _save_and_check(monkeypatch, "ssa_catalogue")
    names = ["glmb", "homht_kbest", "rfisst", "gnn", "jpda"]
    timing = pd.DataFrame([dict(tracker=t, n_objects=n, cpu_s_per_scan=1e-4 * n * (i + 1)) for i, t in enumerate(names)
                           for n in (100, 300, 1000)])
    sf.plot_cost(timing, "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "ssa_catalogue/cost")
    per_scan = pd.DataFrame([dict(tracker=t, n_objects=1000, scan=k, n_groups=5 + k % 3 + i, largest_group=2 + k % 4 + i)
                             for i, t in enumerate(names[:3]) for k in range(60)])
    sf.plot_groups(per_scan, "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "ssa_catalogue/groups")
    cfg = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())["ssa_catalogue"]
    rng = np.random.default_rng(0)
    pos = rng.normal(size=(200, 3))
    pos = 7000.0 * pos / np.linalg.norm(pos, axis=1, keepdims=True)
    sf.plot_catalogue(pos, np.arange(200) % 2 == 0, make_radar(cfg), "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "ssa_catalogue/catalogue")
    from hypotrack.experiments.ssa_catalogue.scorecard import COLUMNS

    card = pd.DataFrame([{**{c: float(i + 1) for c in COLUMNS}, "tracker": t, "n_objects": n, "cross_tags_per_1e4": 0.0,
                          "realism_95": np.nan if t == "jpda" else 1.0, "unphysical_hypotheses_max": 90.0 * (i + 1)}
                         for i, t in enumerate(names) for n in (300, 1000)])
    sf.plot_scorecard(card, "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "ssa_catalogue/scorecard")


def test_ssa50_sensitivity_figure():
    from hypotrack.experiments.ssa import sensitivity as sv

    table = pd.DataFrame([dict(p_D=p, clutter_rate=lam, p_n_end_mean=0.9 + 0.01 * lam, low=0.8, high=1.0, n=5,
                               status=("reproduced" if lam == 0 else "inconclusive"))
                          for p in (0.9, 0.95, 0.99) for lam in (0.0, 0.5, 1.0, 2.0)])
    check(sv.plot_sensitivity(table, tolerance=0.05), "ssa50/sensitivity/p_end_grid")


def test_seed_distributions_figure_with_chain_seed_rows_is_legible():
    from hypotrack.experiments.ssa_seeds.figures import CHAIN_COLOR, plot_distributions
    from hypotrack.experiments.ssa_seeds.run import METRICS

    rows, chains = [], []
    for case, trackers, births in (("ssa50", ["rfisst_chain", "rfisst"], 5),
                                   ("ssa15", ["homht", "rfisst_chain", "rfisst", "rfisst_fixed", "homht_births"], 0)):
        for t in trackers:
            for s in range(10):
                row = dict(case=case, tracker=t, label=f"{t} label", births=births,
                           **{m: (0.0 if births == 0 and "birth" in m else 0.5 + 0.01 * s) for m in METRICS})
                rows.append({**row, "seed_index": s})
                if case == "ssa50" and s < 3:
                    chains.append({**row, "chain_index": s})
    fig = plot_distributions(pd.DataFrame(rows), title="SSA verdicts over seeds (document 000 Sec. IV-A, V-A)",
                             per_chain=pd.DataFrame(chains))
    ticks = [t for t in fig.axes[0].get_yticklabels() if t.get_color() == CHAIN_COLOR]
    assert [t.get_text() for t in ticks] == ["ssa50: rfisst_chain label, chain seeds", "ssa50: rfisst label, chain seeds"]
    check(fig, "ssa_seeds/distributions")


def test_a_legend_below_built_from_the_axes_notes_coinciding_series():
    # b drawn exactly over a: without the note the check refuses the figure, with legend_below it says so
    fig, ax = fs.subplots(height=3.0)
    ax.plot([1, 2, 3], [1, 2, 3], label="a")
    ax.plot([1, 2, 3], [1, 2, 3], label="b")
    ax.plot([1, 2, 3], [3, 2, 1], label="c")
    assert any("lies exactly on" in p for p in fs.legibility_problems(fig, 1.0))
    fs.legend_below(fig)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["a", "b (coincides with a)", "c"]
    assert fs.legibility_problems(fig, 1.0) == []
    plt.close(fig)


def test_a_series_coinciding_in_one_panel_is_noted_in_every_panel():
    # the same two implementations in two panels: they coincide in the first only; one legend entry each
    fig, axes = fs.subplots(1, 2, height=3.0)
    for ax, offset in zip(axes, (0.0, 1.0)):
        ax.plot([1, 2, 3], [1, 2, 3], label="peer A", color="tab:blue")
        ax.plot([1, 2, 3], [1 + offset, 2 + offset, 3 + offset], label="peer B", color="tab:orange")
    fs.legend_below(fig)
    assert [t.get_text() for t in fig.legends[0].get_texts()] == ["peer A", "peer B (coincides with peer A in a panel)"]
    assert fs.legibility_problems(fig, 1.0) == []
    plt.close(fig)


def test_ssa_catalogue_fusion_figure(monkeypatch):
    from hypotrack.experiments.ssa_catalogue.fused import SENSOR_SETS, TABLE_COLUMNS, fused_table, plot_fusion

    seen = _save_and_check(monkeypatch, "ssa_catalogue")
    rows = [{**{c: 0.0 for c in TABLE_COLUMNS}, "tracker": t, "sensors": s, "completeness": 0.2 + 0.03 * j,
             "uncorrelated_per_1e4": 250.0 - 80 * j + 5 * i, "gospa_per_object_km": 1.0 - 0.2 * j + 0.05 * i}
            for i, t in enumerate(["glmb", "homht_kbest", "rfisst", "gnn", "jpda"]) for j, s in enumerate(SENSOR_SETS)]
    plot_fusion(fused_table(rows), "x.pdf", "x.png")
    fig, _ = seen.pop()
    check(fig, "ssa_catalogue/fusion")
