"""hypotrack's own tracker kinds, registered at import: the documents' trackers and the δ-GLMB filter.

=============== ====================================================================================
kind            tracker
=============== ====================================================================================
``hfisst``      :func:`hypotrack.hypotheses.hfisst` — H-FISST, exhaustive (document 000)
``rfisst``      :func:`hypotrack.hypotheses.rfisst` — R-FISST, MCMC search (document 000 Sec. III)
``homht``       :func:`hypotrack.hypotheses.homht` — Reid's HOMHT, exhaustive (document 001)
``homht_kbest`` :func:`hypotrack.hypotheses.homht_kbest` — Reid's HOMHT, Murty's k best
``fisst_kbest`` :func:`hypotrack.hypotheses.fisst_kbest` — FISST with Poisson clutter, Murty's k best
``glmb``        :func:`hypotrack.hypotheses.glmb` — δ-GLMB, Gibbs sampling
``glmb_murty``  :func:`hypotrack.hypotheses.glmb_murty` — δ-GLMB, Murty's ranked assignment
``gnn``         :class:`hypotrack.trackers.SingleHypothesisTracker` — global nearest neighbour
``jpda``        the same with joint probabilistic data association
``pdaf``        the same with each track's PDA on its own
``pmbm_murty``  :func:`hypotrack.hypotheses.pmbm_murty` — PMBM, Murty's k best per global hypothesis
``pmbm_gibbs``  :func:`hypotrack.hypotheses.pmbm_gibbs` — PMBM, Gibbs sampling
``pmb_lbp``     :func:`hypotrack.hypotheses.pmb_lbp` — PMB, LBP association marginals (Williams 2015)
=============== ====================================================================================

Their options and defaults are in ``presets.yaml``. A builder takes the problem's birth model in
its own terms (:class:`~.problem.TrackingProblem`); ``population: false`` fixes the number of objects.
"""

from __future__ import annotations

from types import MappingProxyType

from ..hypotheses import presets
from ..trackers import MOfNInitiator, ScanModel, SingleHypothesisTracker
from .spec import BUILTIN, register

__all__ = ["engine_options", "pmbm_options"]


def engine_options(problem, seed, options) -> dict:
    """The :class:`~hypotrack.hypotheses.HypothesisFilter` keywords shared by the engine's presets:
    the problem's scan interval and the family's options (``max_hypotheses``, ``gate_probability``,
    ``cap``, ``merge_duplicates``) with ``seed``, and the problem's ``validity`` test when it has one.
    The known objects are set afterwards (:func:`hypotrack.registry.build` calls ``initialise``)."""
    out = dict(dt=problem.dt, max_hypotheses=options["max_hypotheses"], cap=options["cap"],
               gate_probability=options["gate_probability"], merge_duplicates=options["merge_duplicates"], seed=seed)
    if problem.validity is not None:
        out["validity"] = problem.validity
    return out


def _hfisst(problem, *, seed, population, max_events, **common):
    return presets.hfisst(problem.motion, problem.sensor, max_events=max_events,
                          population=problem.event_population() if population else None,
                          **engine_options(problem, seed, common))


def _rfisst(problem, *, seed, population, n_steps, mcmc_variant, completion_rounds, burn_in, init, **common):
    return presets.rfisst(problem.motion, problem.sensor, n_steps=n_steps, burn_in=burn_in, mcmc_variant=mcmc_variant,
                          init=init, completion_rounds=completion_rounds,
                          population=problem.event_population() if population else None,
                          **engine_options(problem, seed, common))


def _homht(problem, *, seed, population, max_events, **common):
    births = problem.reid_births() if population else {}
    return presets.homht(problem.motion, problem.sensor, max_events=max_events, **births,
                         **engine_options(problem, seed, common))


def _homht_kbest(problem, *, seed, population, k, **common):
    births = problem.reid_births() if population else {}
    return presets.homht_kbest(problem.motion, problem.sensor, k=k, **births, **engine_options(problem, seed, common))


def _fisst_kbest(problem, *, seed, population, k, **common):
    return presets.fisst_kbest(problem.motion, problem.sensor, k=k,
                               population=problem.event_population() if population else None,
                               **engine_options(problem, seed, common))


def _labeled(problem, population):
    if not population:
        raise ValueError("population must be true for the δ-GLMB presets (their births and deaths are the "
                         "labeled multi-Bernoulli's)")
    return problem.labeled_population()


def _glmb(problem, *, seed, population, n_sweeps, **common):
    return presets.glmb(problem.motion, problem.sensor, population=_labeled(problem, population), n_sweeps=n_sweeps,
                        **engine_options(problem, seed, common))


def _glmb_murty(problem, *, seed, population, k, **common):
    return presets.glmb_murty(problem.motion, problem.sensor, population=_labeled(problem, population), k=k,
                              **engine_options(problem, seed, common))


def _single(association):
    def build(problem, *, seed, gate_probability, m_of_n, initial_velocity_std, max_misses, gnn_score,
              new_target_density, min_clutter_rate, jpda_marginals, lazy, lazy_prediction, gate_out_of_view):
        """GNN/JPDA/PDAF (lecture notes 004) with the problem's models; ``seed`` is unused (deterministic)."""
        s = problem.sensor
        clutter = max(max(s.clutter.rate, min_clutter_rate) / s.clutter.region.area, 1e-300)  # scores need β_FA > 0
        beta_nt = problem.seeded_intensity() if new_target_density is None else new_target_density
        m = s.measurement  # a nonlinear one (the radar's, in the sensor frame) has no H: the EKF's Jacobians
        model = ScanModel(getattr(m, "H", None), m.R, s.detection.p_D, gate_probability, clutter, beta_nt,
                          measurement=None if getattr(m, "linear", True) else m)
        seeded = getattr(problem.births, "seeded_density", None)  # a mixture (admissible region): one track per component
        initiator = None if m_of_n is None else MOfNInitiator(problem.motion, model, m=m_of_n[0], n=m_of_n[1],
                                                              initial_velocity_std=initial_velocity_std,
                                                              mixture=seeded if hasattr(seeded, "components") else None)
        return SingleHypothesisTracker(problem.motion, model, association=association, initiator=initiator,
                                       max_misses=max_misses, gnn_score=gnn_score, in_view=problem.in_view,
                                       jpda_marginals=jpda_marginals, lazy=lazy, lazy_prediction=lazy_prediction,
                                       gate_out_of_view=gate_out_of_view, validity=problem.validity,
                                       p_detect=getattr(s.detection, "p_D_of", None))

    build.__name__ = f"_{association}"
    return build


def pmbm_options(problem, seed, options) -> dict:
    """The :class:`~hypotrack.hypotheses.PMBMFilter` keywords of the ``poisson_mb`` family: the problem's scan
    interval and birth model (:func:`hypotrack.hypotheses.presets.pmbm_births`: a labeled multi-Bernoulli
    birth model's terms as Poisson birth components of weight ``r_B``, or as Bernoulli births), the family's
    options and ``seed``. Measurement-driven births have no Gaussian terms to give a Poisson intensity: refused."""
    from ..hypotheses.presets import pmbm_births
    from .problem import MeasurementBirths

    if isinstance(problem.births, MeasurementBirths):
        raise ValueError("births: the PMBM presets take Gaussian birth terms (a LabeledMultiBernoulliPopulation or a "
                         "SingleEventBirthDeath with Gaussian regions), not measurement-driven births")
    population = None if problem.births is None else problem.labeled_population()
    out = dict(options)
    out.update(pmbm_births(population, out.pop("birth")), dt=problem.dt, seed=seed)
    return out


def _pmbm_murty(problem, *, seed, k, **common):
    return presets.pmbm_murty(problem.motion, problem.sensor, k=k, **pmbm_options(problem, seed, common))


def _pmbm_gibbs(problem, *, seed, n_sweeps, **common):
    return presets.pmbm_gibbs(problem.motion, problem.sensor, n_sweeps=n_sweeps, **pmbm_options(problem, seed, common))


def _pmb_lbp(problem, *, seed, **common):
    return presets.pmb_lbp(problem.motion, problem.sensor, **pmbm_options(problem, seed, common))


_BUILDERS = {"hfisst": _hfisst, "rfisst": _rfisst, "homht": _homht, "homht_kbest": _homht_kbest,
             "fisst_kbest": _fisst_kbest, "glmb": _glmb, "glmb_murty": _glmb_murty,
             "gnn": _single("gnn"), "jpda": _single("jpda"), "pdaf": _single("pdaf"),
             "pmbm_murty": _pmbm_murty, "pmbm_gibbs": _pmbm_gibbs, "pmb_lbp": _pmb_lbp}

for _kind, _entry in BUILTIN["kinds"].items():
    register(_kind, _BUILDERS[_kind], family=_entry["family"], description=_entry.get("description", ""),
             options=MappingProxyType(_entry.get("options", {})), defaults=_entry.get("defaults", {}),
             no_fusion=_entry.get("no_fusion", ""))
