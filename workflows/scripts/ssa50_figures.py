"""ssa50: MAP estimates vs truth for every tracker, Figs 6, 8-10, 11 of the primary tracker, OSPA over
time, the completion step's measured effect and the reproduction claims."""

import matplotlib
from hypotrack.reporting.joblog import claims_line, prefix_output

prefix_output(snakemake)  # every line this job prints names the job

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from hypotrack.experiments import ssa as st  # noqa: E402
from hypotrack.reporting.ledger import write_claims, write_macros  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
inp, out, sec = snakemake.input, snakemake.output, snakemake.params.section
settings = {name: st.TrackerSettings.from_config(sec, name) for name in sec["trackers"]}
labels = {name: s.label for name, s in settings.items()}
primary = sec["primary"]
scenario = st.scenario_from_files(snakemake.config, "ssa50", inp.truth, inp.scans, inp.prior)
K = len(scenario.times)
estimate_scans = st.snapshot_scans(K, sec["estimate_snapshots"])
read = {tr: {t: pd.read_csv(inp[f"{tr}_{t}"]) for t in ("summary", "map_estimates", "weights", "cardinality",
                                                         "timing")} for tr in settings}
# The negative control of every check: the blind tracker (EKF prediction of the initial hypothesis only).
blind, blind_metrics, blind_matched, blind_births = st.evaluate_blind(
    sec, scenario, snapshots=st.snapshot_scans(K, sec["weight_snapshots"]))
blind_claims = st.ssa50_claims(blind_metrics, blind.cardinality, blind.weights, blind_matched, blind_births,
                               estimate_scans=estimate_scans, n_scans=K,
                               error_bound_probability=sec["error_bound_probability"], tracker=st.BLIND_LABEL)
write_table(blind_metrics.assign(tracker=st.BLIND), out.control_metrics)
# "E[N] before the first birth" is about clutter not becoming objects, which a blind tracker cannot do: its
# control is the primary tracker with the clutter density 10^6 times too small (rule ssa50_control_run).
clutter_summary = pd.read_csv(inp.control_clutter).set_index("scan")["expected_number"]
start_control = st.expected_start_claim(clutter_summary, len(scenario.prior_ids), int(clutter_summary.index.max()) + 1, K - 1)
metrics, matched, births, claims = {}, {}, {}, []
for tr in settings:
    metrics[tr], matched[tr] = st.evaluate_configured(sec, scenario, read[tr]["summary"], read[tr]["map_estimates"])
    births[tr] = st.birth_recognition(matched[tr], scenario)
    own = st.ssa50_claims(metrics[tr], read[tr]["cardinality"], read[tr]["weights"], matched[tr], births[tr],
                          estimate_scans=estimate_scans, n_scans=K,
                          error_bound_probability=sec["error_bound_probability"], tracker=labels[tr],
                          per_object_death=settings[tr].kind == "glmb")
    # a row whose control also passes is uninformative
    own = st.attach_controls(own, [c for c in blind_claims if c.key != "ExpectedStart"])
    own = st.attach_controls(own, [start_control], what=st.CLUTTER_DEFECT_LABEL)
    own = st.one_verdict(own, "ssa50", tr, seed_trackers=snakemake.params.seed_trackers,
                         extension=settings[tr].kind == "glmb")  # one verdict per claim; GLMB: not 000's method
    # every row names its tracker; the primary tracker's keys stay unprefixed (the paper quotes them)
    claims += st.labelled(own, labels[tr], "" if tr == primary else f"{tr}_")
all_metrics = pd.concat([m.assign(tracker=tr) for tr, m in metrics.items()], ignore_index=True)
write_table(all_metrics, out.metrics)
write_table(pd.concat([b.assign(tracker=tr) for tr, b in births.items()], ignore_index=True), out.births)
snapshots = matched[primary][matched[primary]["scan"].isin(estimate_scans)]
write_table(snapshots, out.snapshots)

agreements = {tr: st.map_agreement(read[tr]["map_estimates"], read[primary]["map_estimates"], scenario.prior_ids)
              for tr in settings if tr != primary}
table = st.completion_table({tr: r["summary"] for tr, r in read.items()}, settings, agreements,
                            reference=primary)
timing = st.completion_timing({tr: r["timing"] for tr, r in read.items()}, settings)
write_table(table, out.completion)
write_table(timing, out.completion_timing)
print(table.to_string(index=False), "\n", timing.to_string(index=False), flush=True)
timing_claims, timing_macros = [], {}
pair = st.completion_pair(settings)
if pair:
    extra, macros, timing_claims, timing_macros = st.completion_claims(
        "ssa50", table, timing, pair, reference_label=labels[pair[0]])
    claims += extra
    write_macros("ssa50", macros, out.macros)
else:
    write_macros("ssa50", {}, out.macros)
write_macros("ssa50", timing_macros, out.timing_macros)

n_known, n_all = len(scenario.prior_ids), scenario.params.n_objects
what = f"{labels[primary]}; {n_all} objects: {n_known} in the initial hypothesis, {n_all - n_known} births"
st.save_figure(st.plot_weight_snapshots(read[primary]["weights"], K,
                                        title=f"Hypothesis weights during the run ({what})"),
               out.fig6_pdf, out.fig6_png)
fig8 = st.plot_estimate_snapshots(snapshots, scenario.fov, K, column_titles=[f"{labels[primary]}, top hypothesis"],
                                  birth_ids=scenario.birth_ids,
                                  title=f"True positions and top-hypothesis estimates ({what})")
st.save_figure(fig8, out.fig8_pdf, out.fig8_png)
st.save_figure(st.plot_expected_number(metrics[primary], read[primary]["cardinality"],
                                       title=f"Expected number of objects ({what})"),
               out.fig11_pdf, out.fig11_png)
st.save_figure(st.plot_ospa(all_metrics, st.OSPASettings(**sec["ospa"]), labels=labels,
                            title=f"OSPA of the top-hypothesis estimates ({n_all} objects, {n_all - n_known} births)"),
               out.ospa_pdf, out.ospa_png)
print(claims_line(write_claims(claims, out.claims), out.claims), flush=True)
write_claims(timing_claims, out.timing_claims)
