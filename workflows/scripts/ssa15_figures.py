"""ssa15: R-FISST vs HOMHT agreement, Figs 12-14, OSPA of both and the reproduction claims."""

import matplotlib

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from hypotrack.experiments import ssa_tracking as st  # noqa: E402
from hypotrack.report import write_claims  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
inp, out, sec = snakemake.input, snakemake.output, snakemake.params.section
trackers = list(snakemake.params.trackers)
scenario = st.scenario_from_files(snakemake.config, "ssa15", inp.truth, inp.scans, inp.prior)
K = len(scenario.times)
maps = {tr: pd.read_csv(inp[f"{tr}_map"]) for tr in trackers}
metrics, matched = [], []
for tr in trackers:
    m, mt = st.evaluate_configured(sec, scenario, pd.read_csv(inp[f"{tr}_summary"]), maps[tr])
    metrics.append(m.assign(tracker=tr))
    matched.append(mt.assign(tracker=tr))
metrics = pd.concat(metrics, ignore_index=True)
matched = pd.concat(matched, ignore_index=True)
ospa_settings = st.OSPASettings(**sec["ospa"])
agreement = st.map_agreement(maps[trackers[0]], maps[trackers[1]], scenario.prior_ids, c=ospa_settings.c_in_view,
                             p=ospa_settings.p)
snapshot_scans = st.snapshot_scans(K, sec["snapshots"])
snapshots = matched[matched["scan"].isin(snapshot_scans)]
write_table(metrics, out.metrics)
write_table(agreement, out.agreement)
write_table(snapshots, out.snapshots)

names = [st.TRACKER_NAMES[tr] for tr in trackers]
what = f"{scenario.params.n_objects} objects, all known and starting in view; same EKF"
st.save_figure(st.plot_estimate_snapshots(snapshots, scenario.fov, K, columns=trackers, column_titles=names,
                                          title=f"True positions and MAP estimates of {' and '.join(names)} ({what})"),
               out.fig12_pdf, out.fig12_png)
st.save_figure(st.plot_comparison(agreement, metrics, ospa_settings, names=names, trackers=trackers,
                                  title=f"{' vs '.join(names)} ({what})"),
               out.comparison_pdf, out.comparison_png)
claims = st.ssa15_claims(metrics, agreement, matched, estimate_scans=snapshot_scans, n_scans=K,
                         error_bound_probability=sec["error_bound_probability"], trackers=trackers)
print(write_claims(claims, out.claims).to_string(index=False), flush=True)
