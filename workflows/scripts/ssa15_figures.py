"""ssa15: MAP agreement of the compared trackers, Figs 12-14, OSPA of every tracker and the claims."""

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
scenario = st.scenario_from_files(snakemake.config, "ssa15", inp.truth, inp.scans, inp.prior)
K = len(scenario.times)
maps = {tr: pd.read_csv(inp[f"{tr}_map"]) for tr in labels}
metrics, matched = [], []
for tr in labels:
    m, mt = st.evaluate_configured(sec, scenario, pd.read_csv(inp[f"{tr}_summary"]), maps[tr])
    metrics.append(m.assign(tracker=tr))
    matched.append(mt.assign(tracker=tr))
# The negative control of every check: the blind tracker (EKF prediction of the initial hypothesis only).
blind, blind_metrics, blind_matched, _ = st.evaluate_blind(sec, scenario)
metrics = pd.concat(metrics, ignore_index=True)
matched = pd.concat(matched, ignore_index=True)
ospa_settings = st.OSPASettings(**sec["ospa"])
agreements = {(a, b): st.map_agreement(maps[a], maps[b], scenario.prior_ids, c=ospa_settings.c_in_view,
                                       p=ospa_settings.p) for a, b in sec["comparisons"]}
reference = sec["comparisons"][0][1]
blind_agreement = st.map_agreement(blind.map_estimates, maps[reference], scenario.prior_ids,
                                   c=ospa_settings.c_in_view, p=ospa_settings.p)
write_table(blind_metrics.assign(tracker=st.BLIND), out.control_metrics)
snapshot_scans = st.snapshot_scans(K, sec["snapshots"])
snapshots = matched[matched["scan"].isin(snapshot_scans)]
write_table(metrics, out.metrics)
write_table(pd.concat([ag.assign(tracker_a=a, tracker_b=b) for (a, b), ag in agreements.items()]),
            out.agreement)
write_table(snapshots, out.snapshots)

paper_pair = list(sec["comparisons"][0])
what = f"{scenario.params.n_objects} objects, all known and starting in view; same EKF"
st.save_figure(st.plot_estimate_snapshots(snapshots, scenario.fov, K, columns=paper_pair,
                                          column_titles=[labels[tr] for tr in paper_pair],
                                          title=f"True positions and MAP estimates ({what})"),
               out.fig12_pdf, out.fig12_png)
st.save_figure(st.plot_comparison(agreements, metrics, ospa_settings, labels=labels,
                                  title=f"{' vs '.join(labels[tr] for tr in paper_pair)} ({what})"),
               out.comparison_pdf, out.comparison_png)
# The completion step's effect: children found, and each R-FISST's MAP agreement with the paper pair's reference.
table = st.completion_table({tr: pd.read_csv(inp[f"{tr}_summary"]) for tr in labels}, settings,
                            {a: ag for (a, b), ag in agreements.items() if b == reference}, reference=reference)
timing = st.completion_timing({tr: pd.read_csv(inp[f"{tr}_timing"]) for tr in labels}, settings)
write_table(table, out.completion)
write_table(timing, out.completion_timing)
print(table.to_string(index=False), "\n", timing.to_string(index=False), flush=True)
extra, macros, timing_claims, timing_macros = [], {}, [], {}
pair = st.completion_pair(settings)
if pair:
    extra, macros, timing_claims, timing_macros = st.completion_claims("ssa15", table, timing, pair,
                                                                       reference_label=labels[reference])
write_macros("ssa15", macros, out.macros)
write_macros("ssa15", timing_macros, out.timing_macros)
write_claims(timing_claims, out.timing_claims)
claims = st.ssa15_claims(pd.concat([metrics, blind_metrics.assign(tracker=st.BLIND)], ignore_index=True),
                         agreements, pd.concat([matched, blind_matched.assign(tracker=st.BLIND)], ignore_index=True),
                         estimate_scans=snapshot_scans, n_scans=K,
                         error_bound_probability=sec["error_bound_probability"], labels=labels,
                         red_star_tolerance=sec["red_star_tolerance"],
                         max_ospa_km=st.single_return_error_km(scenario), control=st.BLIND,
                         control_agreement=blind_agreement)
claims = st.one_verdict(claims, "ssa15", paper_pair[0], seed_trackers=snakemake.params.seed_trackers) + extra
print(claims_line(write_claims(claims, out.claims), out.claims), flush=True)
