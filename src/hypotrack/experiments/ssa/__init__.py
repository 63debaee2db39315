"""SSA tracking experiments of document 000: hypothesis filters over the space-object scenarios.

Two experiments (document 000 Sec. IV-A and V-A; DESIGN.md §5):

* ``ssa50`` — R-FISST on 50 objects of which the initial hypothesis knows 45; the other 5 are
  births that enter the field of view during the run. Figures: hypothesis-weight snapshots
  (Fig. 6), truth vs top-hypothesis estimates (Figs 8–10), expected number of objects over
  time, 45 → 50 (Fig. 11), OSPA over time.
* ``ssa15`` — R-FISST and HOMHT with the same EKF on 15 objects that all start in view.
  Figures: estimates at the start, middle and end (Figs 12–14), per-scan agreement of the
  two maximum-a-posteriori (MAP) hypotheses, OSPA of both.

One module per step of the data's way; each step reads and writes tables:

1. :mod:`.scenario` — :func:`scenario_from_tables` rebuilds the scenario (models, truth, scans,
   initial hypothesis) from the files of the ``ssa`` rule, so the trackers see exactly the
   saved data;
2. :mod:`.trackers` — :func:`make_tracker` builds a tracker from :class:`TrackerSettings`
   (a named tracker of a config section); :mod:`.run` — :func:`run_tracker` runs it and
   records, per scan, the posterior summaries (expected number of objects, cardinality
   distribution, MAP estimates, hypothesis weights at snapshot scans) — :class:`TrackingRun`;
3. :mod:`.evaluation` — :func:`evaluate_map` compares the MAP estimates with the truth: OSPA
   over the objects in view and over the catalogue, and the paper's "green circle / red star"
   verdict of every estimate (Fig. 7: an estimate is correct when the true object lies inside
   its error bound); :func:`map_agreement` compares two trackers' MAP hypotheses scan by scan;
4. :mod:`.figures` draws the figures from those tables only (:mod:`.scenario_figures` the scenario itself);
5. :mod:`.controls` — the negative control of every check: the blind tracker (EKF prediction of
   the initial hypothesis, no measurement ever used, no births), :func:`blind_run`, scored by the
   same evaluation and claim code; :func:`attach_controls` fills the ledger's ``control`` column;
6. :mod:`.claims` — ``ssa50_claims`` / ``ssa15_claims`` state what was and was not reproduced;
   ``completion_*`` measure what this project's completion step (R-FISST's chain followed by a
   deterministic neighbour search) changes against the paper's chain alone.

Conventions
-----------
* The initial hypothesis is the objects' state at the first scan time; the filter processes
  the scans after it (scan 0's returns are not used), and scan 0 of every table is the
  initial hypothesis itself.
* An object is *in the catalogue* at scan ``k`` when the initial hypothesis holds it or it
  has been in the field of view at some scan ``<= k`` (a birth the filter could know of).
  The true number of objects of Fig. 11 is the catalogue size: 45 rising to 50.
* Estimates are matched to true objects by label: an object of the initial hypothesis keeps
  its id as the label of its track, so a track swap between two objects shows as two
  incorrect estimates. Tracks born in the filter are matched to the catalogue's births by
  optimal assignment on the Mahalanobis distance.
* An estimate is *correct* when the true position lies inside its ``error_bound_probability``
  position ellipse: ``d² = (x − x̂)ᵀ P⁻¹ (x − x̂) <= χ²₂(P)``.
* Times are reported in hours; positions in km (figures in 10³ km).
"""

from __future__ import annotations

from .claims import (
    completion_claims,
    completion_pair,
    completion_table,
    completion_timing,
    expected_start_claim,
    labelled,
    one_verdict,
    seed_claim_id,
    ssa15_claims,
    ssa50_claims,
)
from .controls import (
                         BLIND,
                         BLIND_LABEL,
                         CLUTTER_DEFECT_LABEL,
                         clutter_control_run,
                         clutter_ignoring,
                         attach_controls,
                         blind_predictions,
                         blind_run,
                         evaluate_blind,
                         every_scan_verdict,
                         scan_errors,
                         single_return_error_km,
)
from .evaluation import (
                         AGREEMENT_TOLERANCE_KM,
                         OSPASettings,
                         birth_recognition,
                         evaluate_configured,
                         evaluate_map,
                         map_agreement,
)
from .figures import (
                         plot_comparison,
                         plot_estimate_snapshots,
                         plot_expected_number,
                         plot_ospa,
                         plot_weight_snapshots,
                         save_figure,
)
from .run import (
                         TrackingRun,
                         percent_of_run,
                         run_and_save,
                         run_configured_tracker,
                         run_tracker,
                         snapshot_scans,
)
from .scenario import catalogue_mask, scenario_from_files, scenario_from_tables
from .trackers import TRACKER_KINDS, TRACKER_NAMES, TrackerSettings, make_tracker, tracker_seed

__all__ = [
    "BLIND",
    "BLIND_LABEL",
    "CLUTTER_DEFECT_LABEL",
    "clutter_control_run",
    "clutter_ignoring",
    "attach_controls",
    "blind_predictions",
    "blind_run",
    "evaluate_blind",
    "every_scan_verdict",
    "scan_errors",
    "single_return_error_km",
    "AGREEMENT_TOLERANCE_KM",
    "TRACKER_KINDS",
    "TRACKER_NAMES",
    "OSPASettings",
    "TrackerSettings",
    "TrackingRun",
    "birth_recognition",
    "one_verdict",
    "seed_claim_id",
    "catalogue_mask",
    "completion_claims",
    "completion_pair",
    "completion_table",
    "completion_timing",
    "evaluate_configured",
    "evaluate_map",
    "expected_start_claim",
    "labelled",
    "make_tracker",
    "map_agreement",
    "percent_of_run",
    "plot_comparison",
    "plot_estimate_snapshots",
    "plot_expected_number",
    "plot_ospa",
    "plot_weight_snapshots",
    "run_and_save",
    "run_configured_tracker",
    "run_tracker",
    "save_figure",
    "scenario_from_files",
    "scenario_from_tables",
    "snapshot_scans",
    "ssa15_claims",
    "ssa50_claims",
    "tracker_seed",
]
