"""ssa_catalogue: hypotrack's GNN and JPDA against Stone Soup's on the catalogue scans, side by side.

Stone Soup is a benchmark/test-only dependency; its side is
:class:`hypotrack.interop.stonesoup.peer.StoneSoupPeer` (shared with ``perf_sht_benchmark.py``) with
an EKF predictor on the trackers' motion model; without Stone Soup the rule times hypotrack alone. Both sides
run the known objects with no initiation or deletion, the same EKF dynamics (hypotrack's motion model, two-body plus J2
by default, ``make_motion``, wrapped as a Stone Soup transition model by
:func:`hypotrack.interop.stonesoup.transition.orbit_transition_model`, integrated once per track and scan),
the same linear TEME position measurement, gate, p_D and clutter density (the ENU stand-in radar of
:func:`~hypotrack.experiments.ssa_catalogue.run.peer_config`, whatever radar the section tracks with).
"""
import pandas as pd

from hypotrack.experiments.ssa_catalogue.run import CatalogueSHTStepper, peer_rows, peer_scenario
from hypotrack.experiments.stepping import run_side_by_side
from hypotrack.interop.stonesoup.peer import StoneSoupPeer
from hypotrack.interop.stonesoup.transition import orbit_transition_model
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg, seed = snakemake.params.cfg, snakemake.params.seed  # noqa: F821 (injected by Snakemake)

try:
    import stonesoup  # noqa: F401

    HAVE_STONESOUP = True
except ImportError:
    HAVE_STONESOUP = False
    print("ssa_catalogue: Stone Soup is not installed; timing hypotrack only", flush=True)


def stonesoup_peer(scenario, kind):
    """Stone Soup's ``kind`` on the catalogue scans: EKF predictor on hypotrack's orbit dynamics."""
    from stonesoup.predictor.kalman import ExtendedKalmanPredictor

    predictor = ExtendedKalmanPredictor(orbit_transition_model(scenario.motion))
    return StoneSoupPeer(kind, predictor, scenario.model, (0, 1, 2), scenario.initial_states, scenario.initial_covs,
                         scenario.scan_list(), time0=scenario.times[0])


PEERS = {"gnn": ["GNNWith2DAssignment", "DetectionKDTreeGNN2D"], "jpda": ["JPDAwithEHM2"]}
pc = cfg["peers"]
tables = []
for n in pc["sizes"]:
    ps = peer_scenario(cfg, n, seed)
    for algorithm, peers in PEERS.items():
        steppers = {"hypotrack": CatalogueSHTStepper(ps, algorithm)}
        for kind in peers if HAVE_STONESOUP else []:
            steppers[kind] = stonesoup_peer(ps, kind)
        runs = run_side_by_side(steppers, len(ps.times), max_scans=pc["max_scans"])
        t = peer_rows(runs, algorithm, n, len(ps.initial_states))
        for _, r in t.iterrows():
            print(f"N = {n} {algorithm} {r.implementation}: {r.median_ms:.3g} ms/scan, x{r.peer_over_hypotrack:.3g}, "
                  f"same association on {r.scans_same_association} of {r.scans_compared} scans")
        tables.append(t)
write_table(pd.concat(tables, ignore_index=True), snakemake.output.timing)  # noqa: F821
