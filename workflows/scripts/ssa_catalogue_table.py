"""ssa_catalogue: accuracy and timing tables, ledger rows, macros and figures from the tracker jobs."""
import json

import numpy as np
import pandas as pd

from hypotrack.experiments.ssa_catalogue.figures import plot_catalogue, plot_cost, plot_groups
from hypotrack.experiments.ssa_catalogue.run import build_scenario
from hypotrack.experiments.ssa_catalogue.summary import (
    accuracy_table,
    catalogue_claims,
    catalogue_macros,
    parallel_claims,
    parallel_macros,
    peer_claims,
    peer_macros,
    timing_claims,
    timing_macros,
    timing_table,
)
from hypotrack.reporting.joblog import prefix_output
from hypotrack.reporting.ledger import write_claims, write_macros
from hypotrack.scenarios.catalogue.frames import teme_to_ef
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)
inp, out = snakemake.input, snakemake.output  # noqa: F821
per_scan = pd.concat([pd.read_csv(p) for p in inp.per_scan], ignore_index=True)
assign = pd.concat([pd.read_csv(p) for p in inp.assign], ignore_index=True)
memory = pd.concat([pd.read_csv(p) for p in inp.memory], ignore_index=True)
acc = accuracy_table(per_scan, assign)
tim = timing_table(per_scan, memory)
write_table(acc, out.summary)
write_table(tim, out.timing)
write_claims(catalogue_claims(acc, cfg["reference_tracker"]), out.claims)
par = pd.read_csv(inp.parallel)  # the parallel-groups timing: its rows join the timing ledger
peers = pd.read_csv(inp.peers)  # Stone Soup peers (hypotrack rows only when Stone Soup is absent)
write_claims(timing_claims(tim, cfg["slope_goal"], cfg.get("cpu_per_object_goal_ms")) + parallel_claims(par) + peer_claims(peers), out.timing_claims)
write_macros("ssa_catalogue", catalogue_macros(acc), out.macros)
write_macros("ssa_catalogue", {**timing_macros(tim), **parallel_macros(par), **peer_macros(peers)}, out.timing_macros)
plot_cost(tim, out.cost_pdf, out.cost_png)
plot_groups(per_scan, out.groups_pdf, out.groups_png)
objects, _, sc, _ = build_scenario(cfg, max(cfg["sizes"]), seed)
X, valid = sc.states(np.array([0.0]))
r_ef, _ = teme_to_ef(X[valid[:, 0], :1, :3], X[valid[:, 0], :1, 3:], sc.theta[:1])
plot_catalogue(r_ef[:, 0], (objects["group"] != "active").to_numpy()[valid[:, 0]], sc.sensors[0],
               out.catalogue_pdf, out.catalogue_png)
with open(out.run_config, "w") as fh:  # what ran: the catalogue record checks it (experiments.ssa_catalogue.record)
    json.dump({"seed": seed, "ssa_catalogue": cfg}, fh, indent=1, sort_keys=True)
