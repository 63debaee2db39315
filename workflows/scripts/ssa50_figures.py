"""ssa50: MAP estimates vs truth, Figs 6, 8-10, 11, OSPA over time and the reproduction claims."""

import matplotlib
from hypotrack.experiments.joblog import claims_line, prefix_output

prefix_output(snakemake)  # every line this job prints names the job

matplotlib.use("Agg")
import pandas as pd  # noqa: E402

from hypotrack.experiments import ssa as st  # noqa: E402
from hypotrack.report import write_claims  # noqa: E402
from hypotrack.scenarios.tables import write_table  # noqa: E402

snakemake = globals()["snakemake"]  # injected by Snakemake's script directive
inp, out, sec = snakemake.input, snakemake.output, snakemake.params.section
scenario = st.scenario_from_files(snakemake.config, "ssa50", inp.truth, inp.scans, inp.prior)
K = len(scenario.times)
summary, map_estimates = pd.read_csv(inp.summary), pd.read_csv(inp.map_estimates)
metrics, matched = st.evaluate_configured(sec, scenario, summary, map_estimates)
births = st.birth_recognition(matched, scenario)
estimate_scans = st.snapshot_scans(K, sec["estimate_snapshots"])
snapshots = matched[matched["scan"].isin(estimate_scans)]
weights = pd.read_csv(inp.weights)
cardinality = pd.read_csv(inp.cardinality)
write_table(metrics, out.metrics)
write_table(births, out.births)
write_table(snapshots, out.snapshots)
print(births.to_string(index=False), flush=True)

n_known, n_all = len(scenario.prior_ids), scenario.params.n_objects
what = f"R-FISST; {n_all} objects: {n_known} in the initial hypothesis, {n_all - n_known} births"
st.save_figure(st.plot_weight_snapshots(weights, K, title=f"Hypothesis weights during the run ({what})"),
               out.fig6_pdf, out.fig6_png)
fig8 = st.plot_estimate_snapshots(snapshots, scenario.fov, K, column_titles=["R-FISST top hypothesis"],
                                  birth_ids=scenario.birth_ids,
                                  title=f"True positions and top-hypothesis estimates ({what})")
st.save_figure(fig8, out.fig8_pdf, out.fig8_png)
st.save_figure(st.plot_expected_number(metrics, cardinality, title=f"Expected number of objects ({what})"),
               out.fig11_pdf, out.fig11_png)
st.save_figure(st.plot_ospa(metrics, st.OSPASettings(**sec["ospa"]), labels={"": "R-FISST"},
                            title=f"OSPA of the top-hypothesis estimates ({what})"),
               out.ospa_pdf, out.ospa_png)
claims = st.ssa50_claims(metrics, cardinality, weights, matched, births, estimate_scans=estimate_scans,
                         n_scans=K, error_bound_probability=sec["error_bound_probability"])
print(claims_line(write_claims(claims, out.claims), out.claims), flush=True)
