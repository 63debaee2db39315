"""What the factored engine does to document 000's single-event population, measured on ssa50.

Document 000's population (Eq. 30) allows one birth *or* one death per scan for the whole scene:
``P(no event) = 1 − M_b α − M_d β`` couples every object in view. The factored engine
(:class:`~hypotrack.hypotheses.factored.FactoredFilter`) applies the event model per group — up to
one event per group and scan, ``M_d`` the group's objects in view — so its prior differs (module
docstring of :mod:`hypotrack.hypotheses.factored`, "When the factored posterior equals the
unfactored one"). This module measures the difference on document 000's own problem: the ssa50
scenario (45 known objects, 5 births), R-FISST with the ssa50 section's α, β, birth regions and
``H∞``, on the same scans:

(a) ``unfactored``: the engine (:func:`hypotrack.experiments.ssa.make_tracker`);
(b) ``factored``: the same filter, same chain seed, through
    :meth:`FactoredFilter.from_filter` (``births="coupled"``, the default, and ``split="exact"``
    unless stated: a group splits only where its joint factorises, so no marginal-product
    approximation enters);
(c) ``reseeded``: (a) with another chain seed — R-FISST is a Markov chain Monte Carlo search, so
    two runs of one filter differ; (c) against (a) is the **noise floor** that the factoring
    effect must exceed to say anything (the factored engine draws each group's step from its own
    stream, so (b) never follows (a)'s chain either).

The pairs (:data:`PAIRS`): (b) against (a) and (b) against (c), the factoring effect measured
against each unfactored chain, and (c) against (a), the floor. Both factored pairs are needed: a
chain that wanders (an extra object born of clutter and kept for hundreds of scans) makes every
comparison with it large, so when (a) wanders, (b) against (a) is as large as the floor although
(b) and (c) agree. :func:`against_floor` says "larger than" the floor only when both factored
pairs exceed it by a factor of two (one pair of seeds estimates the floor, so nothing finer is
called a difference), "smaller than" when both stay below half of it, else "about as large as".

The factored engine forms groups from the tracks' validation gates, and ssa50 runs ungated
(document 000's R-FISST samples the whole data association matrix): all three runs get the same
gate (``gate_probability``), so that (a) and (c) are the engine as (b) sees it. Between (b) and (a)
there are then, besides the chain's randomness:

* the **per-group event model** (the effect measured);
* the **per-group hypothesis cap**: each group keeps ``H∞`` hypotheses (and a merge keeps the
  best ``H∞`` of the product), so the factored filter holds more joint hypotheses than (a);
* H-FISST's count term ``−log(m!/(m − n)!)`` (document 000 Eq. 8), evaluated per group on the
  group's own returns — like the population, not separable; R-FISST's weights carry it, so the
  measurement is of document 000's R-FISST through the factored engine, the two together.

How far (b) factors is the engine's business, recorded per scan (``groups``, ``largest_group``):
with this population it merges much — a birth region's term links every return in the region, so
the objects with a return in one region step as one group, and an undetected birth (a track with
the region's uniform position pdf, thousands of km wide) gates every return there; with
``split="exact"`` a group whose joint does not factorise stays together. Objects that no return
and no birth term reach stay groups of their own, each with its own ``P(no event)``.

Per scan (:func:`compare_runs`): each run's expected number of objects E[N], P(N = true number)
(the catalogue size of :func:`~hypotrack.experiments.ssa.catalogue_mask`, 45 rising to 50), the
number of objects its MAP hypothesis holds; per pair the total variation between the cardinality
distributions (:func:`~hypotrack.hypotheses.cardinality_total_variation`); the factored filter's
groups. :func:`pair_summary` reduces it per pair, :func:`single_event_claims` and
:func:`single_event_macros` give the ledger rows and the report's numbers.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..._validation import check_int, check_probability
from ...hypotheses.factored import SPLITS, FactoredFilter, cardinality_total_variation
from ...reporting.ledger import Claim
from ..ssa.scenario import catalogue_mask
from ..ssa.trackers import TrackerSettings, make_tracker, tracker_seed
from ..stepping import Clocks

__all__ = ["PAIRS", "RUNS", "SingleEventSettings", "against_floor", "compare_runs", "pair_summary", "single_event_claims",
           "single_event_comparison", "single_event_filters", "single_event_macros"]

EXPERIMENT = "ssa_catalogue"
SEED_KEY = "ssa_catalogue_single_event"  # the runs' random streams: tracker_seed(seed, SEED_KEY, run)
#: The three runs, (a) first: every pair is a run against it.
RUNS = ("unfactored", "factored", "reseeded")
#: ``pair: (run, reference)``: the factoring effect against each unfactored chain, and the chain's noise floor.
PAIRS = {"factoring": ("factored", "unfactored"), "factoring_reseeded": ("factored", "reseeded"),
         "chain_noise": ("reseeded", "unfactored")}
#: A factor this large between the factoring pairs' mean TV and the floor's counts as a difference.
FLOOR_FACTOR = 2.0


@dataclass(frozen=True)
class SingleEventSettings:
    """The ``ssa_catalogue.single_event`` config section.

    Parameters
    ----------
    tracker : str
        An R-FISST tracker of the ``ssa50`` section (its chain variant, completion rounds, and the
        section's population and ``H∞``).
    n_steps : int
        MCMC proposals per parent per scan (replaces the tracker's).
    gate_probability : float
        Validation gate of all three runs, in (0, 1) (the factored engine's groups come from it).
    split : {"exact", "marginal", "never"}
        The factored run's split (:class:`FactoredFilter`).
    n_scans : int or None
        Scans run (scan 0, the initial hypothesis, included); ``None``: the scenario's.
    """

    tracker: str = "rfisst_chain"
    n_steps: int = 10_000
    gate_probability: float = 0.999999999
    split: str = "exact"
    n_scans: int | None = None

    def __post_init__(self):
        check_int(self.n_steps, "n_steps", minimum=1)
        check_probability(self.gate_probability, "gate_probability", low_open=True, high_open=True)
        if self.split not in SPLITS:
            raise ValueError(f"split must be one of {SPLITS}, got {self.split!r}")
        if self.n_scans is not None:
            check_int(self.n_scans, "n_scans", minimum=2)

    @classmethod
    def from_config(cls, section: Mapping) -> SingleEventSettings:
        return cls(**dict(section))

    def tracker_settings(self, ssa50: Mapping) -> TrackerSettings:
        """The R-FISST settings of ``tracker`` in the ``ssa50`` section, with this gate and ``n_steps``."""
        base = TrackerSettings.from_config(ssa50, self.tracker)
        if base.kind != "rfisst" or not base.population:
            raise ValueError(f"tracker must be an R-FISST tracker with births and deaths in ssa50.trackers, "
                             f"got {self.tracker!r} ({base.label})")
        return base.with_options(n_steps=self.n_steps, gate_probability=self.gate_probability)


def single_event_filters(scenario, tracker: TrackerSettings, master_seed: int, *, split: str = "exact") -> dict:
    """The three filters of the comparison, each started from the scenario's initial hypothesis:
    (a) and (b) from one chain seed, (c) from another (``tracker_seed(master_seed, SEED_KEY, run)``)."""
    seed = tracker_seed(master_seed, SEED_KEY, "unfactored")
    return {"unfactored": make_tracker(scenario, tracker, seed),
            # from_filter copies the filter's generator: (b) starts from (a)'s seed
            "factored": FactoredFilter.from_filter(make_tracker(scenario, tracker, seed), split=split),
            "reseeded": make_tracker(scenario, tracker, tracker_seed(master_seed, SEED_KEY, "reseeded"))}


def compare_runs(filters: Mapping, scans: Sequence, n_true: Sequence[int], *,
                 progress: Callable[[str], None] | None = None, n_progress: int = 10) -> tuple[pd.DataFrame, dict]:
    """Step every filter of ``filters`` (names :data:`RUNS`) through the same scans; per scan, compare.

    Parameters
    ----------
    filters : mapping
        ``"unfactored"``, ``"factored"``, ``"reseeded"`` → a filter with ``step(Z, time)`` returning
        a posterior (``cardinality``, ``expected_number``, ``map_estimate``).
    scans : sequence of (t, Z)
        Scan 0 is the filters' start time (its returns are not used); the filters step from scan 1.
    n_true : sequence of int
        The true number of objects at each scan (``len(scans)`` values).

    Returns
    -------
    per_scan : DataFrame
        One row per scan from 1: ``scan, time, n_returns, n_true``; per run ``expected_number_<run>``,
        ``p_true_<run>`` (P(N = n_true)), ``map_n_<run>`` (objects in the MAP hypothesis); per pair
        (:data:`PAIRS`) ``tv_<pair>`` (cardinality total variation between its two runs) and
        ``map_same_n_<pair>``; the factored filter's ``groups`` and ``largest_group`` (objects).
    cpu_seconds : dict
        CPU seconds of each run's steps.
    """
    missing = set(RUNS) - set(filters)
    if missing:
        raise ValueError(f"filters must hold the runs {RUNS}, missing {sorted(missing)}")
    n_true = np.asarray(n_true, dtype=np.int64)
    if n_true.shape != (len(scans),):
        raise ValueError(f"n_true must hold one number per scan ({len(scans)}), got shape {n_true.shape}")
    if len(scans) < 2:
        raise ValueError("scans must hold the start scan and at least one more")
    cpu = dict.fromkeys(RUNS, 0.0)
    every = max(1, (len(scans) - 1) // max(1, n_progress))
    rows = []
    for k in range(1, len(scans)):
        t, Z = scans[k]
        post = {}
        for name in RUNS:
            with Clocks() as clocks:
                post[name] = filters[name].step(Z, t)
            cpu[name] += clocks.cpu
        n = int(n_true[k])
        row = {"scan": k, "time": t, "n_returns": len(Z), "n_true": n}
        for name, p in post.items():
            card = np.asarray(p.cardinality, dtype=float)
            row[f"expected_number_{name}"] = float(p.expected_number)
            row[f"p_true_{name}"] = float(card[n]) if n < len(card) else 0.0
            row[f"map_n_{name}"] = int(p.map_estimate.n_objects)
        for pair, (name, ref) in PAIRS.items():
            row[f"tv_{pair}"] = cardinality_total_variation(post[ref].cardinality, post[name].cardinality)
            row[f"map_same_n_{pair}"] = row[f"map_n_{name}"] == row[f"map_n_{ref}"]
        stats = getattr(filters["factored"], "last_stats", {})
        row["groups"], row["largest_group"] = int(stats.get("n_groups", 0)), int(stats.get("largest_group", 0))
        rows.append(row)
        if progress is not None and (k % every == 0 or k == len(scans) - 1):
            progress(f"single event scan {k}/{len(scans) - 1}: E[N] {row['expected_number_unfactored']:.3f} "
                     f"(factored {row['expected_number_factored']:.3f}, reseeded {row['expected_number_reseeded']:.3f}), "
                     f"TV {row['tv_factoring']:.3g} and {row['tv_factoring_reseeded']:.3g} (floor "
                     f"{row['tv_chain_noise']:.3g}), {row['groups']} groups; "
                     "CPU s " + ", ".join(f"{v:.0f}" for v in cpu.values()))
    return pd.DataFrame(rows), cpu


def single_event_comparison(scenario, settings: SingleEventSettings, ssa50: Mapping, master_seed: int, *,
                            progress: Callable[[str], None] | None = None) -> tuple[pd.DataFrame, dict]:
    """The measurement on an SSA scenario (ssa50): :func:`single_event_filters` run by :func:`compare_runs`
    over the first ``settings.n_scans`` scans. ``ssa50`` is the config section naming the tracker."""
    tracker = settings.tracker_settings(ssa50)
    scans = scenario.scan_list()
    if settings.n_scans is not None:
        scans = scans[:settings.n_scans]
    n_true = catalogue_mask(scenario).sum(axis=1)[:len(scans)]
    filters = single_event_filters(scenario, tracker, master_seed, split=settings.split)
    return compare_runs(filters, scans, n_true, progress=progress)


def pair_summary(per_scan: pd.DataFrame) -> pd.DataFrame:
    """Per pair of :data:`PAIRS` (``run`` against ``reference``), over the scans of ``per_scan``:
    ``n_scans``, the mean and largest cardinality TV (and the first scan reaching it), the mean
    ``|ΔE[N]|``, the share of scans whose MAP hypotheses hold the same number of objects, and the
    last scan's TV, ``ΔE[N]`` (run − reference) and P(N = true) of both runs."""
    if len(per_scan) == 0:
        raise ValueError("per_scan must hold at least one scan")
    last = per_scan.iloc[-1]
    rows = []
    for pair, (name, ref) in PAIRS.items():
        tv = per_scan[f"tv_{pair}"].to_numpy(dtype=float)
        den = per_scan[f"expected_number_{name}"].to_numpy(dtype=float) - per_scan[f"expected_number_{ref}"].to_numpy(dtype=float)
        rows.append({"pair": pair, "run": name, "reference": ref, "n_scans": len(per_scan), "tv_mean": float(tv.mean()),
                     "tv_max": float(tv.max()), "tv_max_scan": int(per_scan["scan"].iloc[int(np.argmax(tv))]),
                     "abs_den_mean": float(np.abs(den).mean()),
                     "map_same_n_share": float(per_scan[f"map_same_n_{pair}"].astype(bool).mean()),
                     "tv_final": float(tv[-1]), "den_final": float(den[-1]),
                     "p_true_final": float(last[f"p_true_{name}"]),
                     "p_true_final_reference": float(last[f"p_true_{ref}"])})
    return pd.DataFrame(rows)


def against_floor(summary: pd.DataFrame, factor: float = FLOOR_FACTOR) -> str:
    """The factoring effect's mean TV against the floor's: ``"larger than"`` when both factored
    pairs exceed ``factor`` × the floor, ``"smaller than"`` when both stay below floor / ``factor``,
    else ``"about as large as"`` (module docstring)."""
    s = summary.set_index("pair")["tv_mean"]
    effect, floor = s[["factoring", "factoring_reseeded"]], s["chain_noise"]
    if (effect > factor * floor).all():
        return "larger than"
    if (effect * factor < floor).all():
        return "smaller than"
    return "about as large as"


def _g(x: float, digits: int = 2) -> str:
    return f"{x:.{digits}g}"


def single_event_claims(summary: pd.DataFrame, per_scan: pd.DataFrame, settings: SingleEventSettings,
                        h_inf: int) -> list[Claim]:
    """Two extension rows (evidence: measurement), each with the factoring effect (against both
    unfactored chains) and the chain's noise floor: the cardinality TV, and E[N] with the MAP count
    agreement."""
    s = summary.set_index("pair")
    f, r, c = s.loc["factoring"], s.loc["factoring_reseeded"], s.loc["chain_noise"]
    what = (f"R-FISST on ssa50 ({int(f.n_scans)} scans, {settings.n_steps:,} proposals, gate P_G = "
            f"{settings.gate_probability:.12g}, H_inf = {h_inf} per group, split '{settings.split}'), same scans; "
            f"factored against the unfactored run and against its reseeded twin; floor: the two unfactored runs "
            f"(chain seeds alone differ)")
    groups = (f"factored groups per scan {per_scan['groups'].mean():.3g} on average, largest "
              f"{int(per_scan['largest_group'].max())} objects")
    differs = ("differences besides the chain: the per-group event model, the per-group cap, and H-FISST's count "
               "term per group (Eq. 8)")
    source = "extension (factored engine, document 000 Eq. 30)"
    return [
        Claim(EXPERIMENT, "cardinality TV between factored (per-group events) and unfactored R-FISST, document 000's "
              "single-event population", source, "--",
              f"TV mean {_g(f.tv_mean)} (max {_g(f.tv_max)}) and {_g(r.tv_mean)} (max {_g(r.tv_max)}) vs chain-seed "
              f"floor {_g(c.tv_mean)} (max {_g(c.tv_max)})", "--", "extension",
              f"{what}; effect {against_floor(summary)} the floor (a factor of {FLOOR_FACTOR:g} either way counts); "
              f"last scan TV {_g(f.tv_final)} and {_g(r.tv_final)} (floor {_g(c.tv_final)}); {groups}; {differs}",
              "measurement", key="single_event_tv"),
        Claim(EXPERIMENT, "expected number of objects, factored (per-group events) against unfactored R-FISST, "
              "document 000's single-event population", source, "--",
              f"mean |ΔE[N]| {_g(f.abs_den_mean)} and {_g(r.abs_den_mean)} vs chain-seed floor {_g(c.abs_den_mean)}",
              "--", "extension",
              f"{what}; last scan ΔE[N] {f.den_final:+.2g} and {r.den_final:+.2g} (floor {c.den_final:+.2g}), "
              f"P(N = true) {f.p_true_final:.3f} factored, {f.p_true_final_reference:.3f} unfactored, "
              f"{r.p_true_final_reference:.3f} reseeded; MAP holds the same number of objects at "
              f"{100 * f.map_same_n_share:.3g} % and {100 * r.map_same_n_share:.3g} % of scans (floor "
              f"{100 * c.map_same_n_share:.3g} %); {differs}", "measurement", key="single_event_expected_number"),
    ]


def single_event_macros(summary: pd.DataFrame, per_scan: pd.DataFrame, settings: SingleEventSettings) -> dict:
    """The report's numbers (``\\htSsaCatalogueSingleEvent...``): per pair (no tag: factored against
    unfactored; ``Reseeded``: factored against the reseeded run; ``Floor``) TV mean/max/last, mean
    ``|ΔE[N]|`` and MAP agreement (%); groups, scans, the gate's miss probability ``1 − P_G``, and
    ``AgainstFloor`` (:func:`against_floor`: the text's comparison follows the run) with its
    ``FloorFactor``."""
    s = summary.set_index("pair")
    v = {"SingleEventScans": int(s.loc["factoring", "n_scans"]),
         "SingleEventAgainstFloor": against_floor(summary), "SingleEventFloorFactor": f"{FLOOR_FACTOR:g}",
         "SingleEventGateMiss": f"{1.0 - settings.gate_probability:.1g}",
         "SingleEventGroupsMean": f"{per_scan['groups'].mean():.3g}",
         "SingleEventLargestGroup": int(per_scan["largest_group"].max())}
    for pair, tag in (("factoring", ""), ("factoring_reseeded", "Reseeded"), ("chain_noise", "Floor")):
        r = s.loc[pair]
        v[f"SingleEvent{tag}TvMean"] = _g(r.tv_mean)
        v[f"SingleEvent{tag}TvMax"] = _g(r.tv_max)
        v[f"SingleEvent{tag}TvFinal"] = _g(r.tv_final)
        v[f"SingleEvent{tag}DenMean"] = _g(r.abs_den_mean)
        v[f"SingleEvent{tag}MapSame"] = f"{100 * r.map_same_n_share:.3g}"
    return v
