"""The hypothesis engine against the independent oracle of :mod:`.fisst_oracle` (document 001 Sec. V).

On small random scans (M ≤ 4 objects, m ≤ 4 returns, one birth pixel, deaths, Poisson clutter)
the engine's one-scan children (:meth:`hypotrack.hypotheses.HypothesisFilter.expand`) are
compared, child by child, with the oracle's brute-force evaluation of the seeds' densities:

* FISST with births and deaths (engine: :class:`~hypotrack.hypotheses.FISSTPoissonWeights` with
  :class:`~hypotrack.hypotheses.BinomialPopulation` in the Poisson limit) — same children, same
  posterior, same normaliser; the undetected-birth ratios of Eq. 39 come out of the densities;
* Reid's HOMHT (engine: :class:`~hypotrack.hypotheses.ReidWeights` with seeded new targets) —
  same posterior as Reid's formula, and (oracle against oracle) as FISST over the association
  children when ``β_NT = α p_D / V̄`` (document 001 Sec. V-A, extended to births).

Returns lie at least 20 measurement standard deviations inside the birth pixel, where the engine's
``∫ N(z; x, R) U(x; pixel) dx = 1/V̄`` holds to far below the tolerance (the oracle integrates exactly).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ...hypotheses import ExhaustiveGenerator, FISSTPoissonWeights, HypothesisFilter, ReidWeights
from ...hypotheses.population_events import BinomialPopulation
from ...models import ConstantVelocity
from ...models.population import UniformBirthDensity
from ...models.sensors import Box, DetectionModel, LinearPositionSensor, PoissonClutter, Sensor
from ...reporting.ledger import Claim
from ...reporting.verdict import with_control
from .fisst_oracle import ASSOCIATION, NEW_TARGET, OracleScene, fisst_children, normalise, reid_children, \
    undetected_birth_ratios

__all__ = ["random_scene", "engine_children", "oracle_table", "oracle_claims"]

EDGE = 20.0  # returns and prior positions stay this many measurement s.d. inside the pixel


def random_scene(cfg, rng, size=None) -> dict:
    """A random small scan: priors, returns near some objects and elsewhere in the pixel.

    ``size = (M, m)`` fixes the numbers of objects and returns; by default both are drawn.
    """
    L, sd = float(cfg["pixel_size"]), float(cfg["measurement_std"])
    M = int(rng.integers(0, int(cfg["max_objects"]) + 1)) if size is None else size[0]
    m = int(rng.integers(0, int(cfg["max_returns"]) + 1)) if size is None else size[1]
    lo, hi = 2 * EDGE * sd, L - 2 * EDGE * sd
    centre = rng.uniform(lo + 10 * sd, hi - 10 * sd, 2)
    pos = centre + rng.normal(0, 3 * sd, (M, 2))  # close objects: the association is ambiguous
    means = np.column_stack([pos, rng.normal(0, 0.5, (M, 2))]) if M else np.zeros((0, 4))
    covs = np.repeat(np.diag([2.0, 2.0, 0.1, 0.1])[None], M, axis=0)
    near = min(m, M)
    Z = np.vstack([pos[:near] + means[:near, 2:] + rng.normal(0, 2 * sd, (near, 2)),
                   rng.uniform(lo, hi, (m - near, 2))]) if m else np.zeros((0, 2))
    return {"means": means, "covs": covs, "Z": np.clip(Z, EDGE * sd, L - EDGE * sd)}


def _models(cfg):
    L, sd = float(cfg["pixel_size"]), float(cfg["measurement_std"])
    pixel = Box([0.0, 0.0], [L, L])
    sensor = Sensor(LinearPositionSensor(np.eye(2) * sd**2, 4), DetectionModel(float(cfg["p_D"]), pixel),
                    PoissonClutter(float(cfg["clutter_rate"]), pixel))
    return ConstantVelocity(float(cfg["q"])), sensor, UniformBirthDensity(pixel, np.eye(2))


def _oracle_scene(cfg, scene, *, births: bool, new_target_density: float = 0.0) -> OracleScene:
    motion, sensor, _ = _models(cfg)
    L, sd = float(cfg["pixel_size"]), float(cfg["measurement_std"])
    return OracleScene(
        means=scene["means"], covs=scene["covs"], F=motion.F(1.0), Q=motion.Q(1.0),
        H=np.hstack([np.eye(2), np.zeros((2, 2))]), R=np.eye(2) * sd**2, p_D=float(cfg["p_D"]),
        clutter_rate=float(cfg["clutter_rate"]), clutter_volume=L * L, Z=scene["Z"],
        pixel_low=np.zeros(2) if births else None, pixel_high=np.full(2, L) if births else None,
        alpha=float(cfg["alpha"]) if births else 0.0, p_survive=float(cfg["p_survive"]) if births else 1.0,
        new_target_density=new_target_density)


def engine_children(cfg, scene, weights: str) -> dict:
    """The engine's one-scan children ``{(events, kind, arg): log-weight}`` (``"fisst"`` or ``"reid"``)."""
    motion, sensor, birth = _models(cfg)
    if weights == "fisst":
        model = FISSTPoissonWeights()
        population = BinomialPopulation([birth], alpha=float(cfg["alpha"]), p_survive=float(cfg["p_survive"]),
                                        poisson_limit=True)
    else:
        model = ReidWeights(birth_intensity=_new_target_density(cfg), birth_density=birth)
        population = None
    filt = HypothesisFilter(motion, sensor, model, ExhaustiveGenerator(), population=population,
                            max_hypotheses=10**6, means=scene["means"], covs=scene["covs"])
    cs = filt.expand(scene["Z"])
    return {(tuple(int(x) for x in ev), int(k), int(a)): float(w)
            for ev, k, a, w in zip(cs.events, cs.kind, cs.arg, cs.log_weights)}


def _new_target_density(cfg) -> float:
    """Reid's β_NT matching FISST's detected birth: α p_D / V̄."""
    return float(cfg["alpha"]) * float(cfg["p_D"]) / float(cfg["pixel_size"]) ** 2


def _max_dlogp(a: dict, b: dict) -> float:
    if a.keys() != b.keys():
        return np.inf
    pa, pb = normalise(a), normalise(b)
    return max(abs(pa[k] - pb[k]) for k in pa)


def _log_total(d: dict) -> float:
    return float(np.logaddexp.reduce(list(d.values())))


def oracle_table(cfg, seed) -> pd.DataFrame:
    """One row per random scene: engine vs oracle for FISST and Reid, and FISST vs Reid in the oracle.

    ``cfg``: ``n_scenes``, ``max_objects``, ``max_returns``, ``p_D``, ``clutter_rate``, ``alpha``,
    ``p_survive``, ``pixel_size`` (m), ``measurement_std`` (m), ``q`` (CV process noise).
    """
    rows = []
    for i, ss in enumerate(np.random.SeedSequence(seed).spawn(int(cfg["n_scenes"]))):
        # the first scene has the largest size, so that every run covers it
        size = (int(cfg["max_objects"]), int(cfg["max_returns"])) if i == 0 else None
        scene = random_scene(cfg, np.random.default_rng(ss), size)
        of = fisst_children(_oracle_scene(cfg, scene, births=True))
        ef = engine_children(cfg, scene, "fisst")
        beta_nt = _new_target_density(cfg)
        orr = reid_children(_oracle_scene(cfg, scene, births=False, new_target_density=beta_nt))
        er = engine_children(cfg, scene, "reid")
        M = len(scene["means"])
        # FISST association children with the birth pixel's code M read as a Reid new target.
        fa = {(tuple(NEW_TARGET if x == M else x for x in a), k, arg): v
              for (a, k, arg), v in of.items() if k == ASSOCIATION}
        # negative controls: the same oracles without their missed-detection factors (1 - p_D)
        cf = fisst_children(_oracle_scene(cfg, scene, births=True), defect="no_missed_detection")
        cr = reid_children(_oracle_scene(cfg, scene, births=False, new_target_density=beta_nt),
                           defect="no_missed_detection")
        r_control = undetected_birth_ratios(cf)
        r_oracle = undetected_birth_ratios(of)
        r_engine = undetected_birth_ratios(ef) if ef.keys() == of.keys() else np.array([np.inf])
        eq39 = (1 - float(cfg["p_D"])) * float(cfg["alpha"])
        rows.append({
            "scene": i, "n_objects": M, "n_returns": len(scene["Z"]), "n_children": len(of),
            "fisst_same_children": ef.keys() == of.keys(),
            "fisst_max_abs_dlogp": _max_dlogp(ef, of),
            "fisst_abs_dlog_normaliser": abs(_log_total(ef) - _log_total(of)),
            "reid_same_children": er.keys() == orr.keys(),
            "reid_max_abs_dlogp": _max_dlogp(er, orr),
            # Reid seeds any number of new targets, one pixel births at most one object: compare the
            # posteriors conditional on the FISST children (all of which Reid has).
            "oracle_fisst_vs_reid_max_abs_dlogp": _max_dlogp(fa, {k: orr[k] for k in fa if k in orr}),
            "eq39_pairs": len(r_oracle),
            "eq39_oracle_rel_dev": float(np.max(np.abs(r_oracle / eq39 - 1), initial=0.0)),
            "eq39_engine_vs_oracle_rel_dev": float(np.max(np.abs(r_engine / r_oracle - 1), initial=0.0))
            if len(r_engine) == len(r_oracle) else np.inf,
            "control_fisst_max_abs_dlogp": _max_dlogp(ef, cf),
            "control_reid_max_abs_dlogp": _max_dlogp(er, cr),
            "control_eq39_rel_dev": float(np.max(np.abs(r_control / eq39 - 1), initial=0.0)),
        })
    return pd.DataFrame(rows)


def oracle_claims(table: pd.DataFrame, tol: float) -> list:
    """Ledger rows backed by the oracle (evidence "independent oracle"), each with its negative
    control: the same comparison against the oracle without its missed-detection factors
    ``1 − p_D`` (``fisst_children(..., defect="no_missed_detection")``), which must fail it."""
    n = len(table)
    sizes = (f"{n} random scans, up to {table['n_objects'].max()} objects and "
             f"{table['n_returns'].max()} returns")

    def verdict(ok):
        return "reproduced" if ok else "not reproduced"

    fisst = float(max(table["fisst_max_abs_dlogp"].max(), table["fisst_abs_dlog_normaliser"].max()))
    reid = float(max(table["reid_max_abs_dlogp"].max(), table["oracle_fisst_vs_reid_max_abs_dlogp"].max()))
    eq39 = float(max(table["eq39_oracle_rel_dev"].max(), table["eq39_engine_vs_oracle_rel_dev"].max()))
    what = "the oracle without its missed-detection factors 1 − p_D"
    c_fisst = float(table["control_fisst_max_abs_dlogp"].max())
    c_reid = float(table["control_reid_max_abs_dlogp"].max())
    c_eq39 = float(table["control_eq39_rel_dev"].max())
    return [
        with_control(Claim(
            "belief_space", "FISST posterior with births and deaths, independent oracle",
            "001 Eqs. 5-7, 31-33, 59; 000 Eq. 20", "multi-object density", f"max |d log p| = {fisst:.1e}",
            f"{tol:g}", verdict(bool(table["fisst_same_children"].all()) and fisst <= tol),
            f"engine children and posterior against the seeds' densities evaluated by brute force, no code "
            f"shared with the weight models ({sizes}, one birth pixel, deaths, Poisson clutter)",
            "independent oracle", key="FisstOracle"),
            what, f"max |d log p| = {c_fisst:.2g}", c_fisst <= tol),
        with_control(Claim(
            "belief_space", "FISST = HOMHT, independent oracle", "001 Sec. V-A, Eqs. 30, 35", "identical",
            f"max |d log p| = {reid:.1e}", f"{tol:g}",
            verdict(bool(table["reid_same_children"].all()) and reid <= tol),
            "Reid's formula against the engine's HOMHT, and against the FISST density over the association "
            "children with the new-target density alpha p_D / pixel area (births included)",
            "independent oracle", key="FisstHomhtOracle"),
            "Reid's formula without its missed-detection factors 1 − p_D", f"max |d log p| = {c_reid:.2g}",
            c_reid <= tol),
        with_control(Claim(
            "belief_space", "undetected-birth weight ratio, independent oracle", "001 Eq. 39",
            "(1 - p_D) alpha",
            f"max rel. deviation {eq39:.1e}", f"{tol:g} relative",
            verdict(bool(table["eq39_pairs"].sum() > 0) and eq39 <= tol),
            f"{int(table['eq39_pairs'].sum())} twin pairs: the ratio read off the multi-object density and "
            "the engine's ratio for the same children", "independent oracle", key="BirthRatioOracle"),
            what, f"max rel. deviation {c_eq39:.2g}", c_eq39 <= tol),
    ]
