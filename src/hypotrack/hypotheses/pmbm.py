"""The Poisson multi-Bernoulli mixture (PMBM) filter and its track-oriented marginal PMB collapse.

García-Fernández, Williams, Granström & Svensson, "Poisson multi-Bernoulli mixture filter: direct
derivation and implementation", IEEE TAES 54(4), 2018 ("the 2018 paper"); Williams, "Marginal
multi-Bernoulli filters: RFS derivation of MHT, JIPDA and association-based MeMBer", IEEE TAES 51(3),
2015 ("Williams 2015"). The equation numbers of the papers' texts were not at hand: the steps below
cite the theorems and sections and state every formula in full.

The posterior is a Poisson process of undetected objects (:mod:`.pmbm_poisson`) times a mixture of
multi-Bernoulli densities over **global hypotheses**, built track-oriented (the 2018 paper, Sec. III):
a *track* is one potential object, started by a measurement (or a Bernoulli birth, or a known
object); its *local hypotheses* are its association histories, each a Bernoulli with existence
``r`` and a Gaussian ``N(m, P)``. A global hypothesis picks one local hypothesis of every track
(or none: the track does not exist under it, i.e. ``r = 0``) and has a weight. Hypothesis weights
are logarithms throughout.

One ``step(Z)``:

1. **Prediction** (Theorem 1): every local hypothesis ``r ← p_S r``, moments Kalman-predicted;
   Poisson part ``λ^b + p_S f λ^u`` (:meth:`PoissonIntensity.predict`); with ``birth="bernoulli"``
   each birth term is instead a new track with one local hypothesis (``r_B``, its density) present
   in every global hypothesis (the δ-GLMB's labeled-Bernoulli birth; see the 2018 paper's Sec. V on
   the δ-GLMB as a special case of the PMBM).
2. **Single-target hypotheses** (Theorem 2), computed once per scan for every local hypothesis:
   missed, ``w ← w (1 − r p_D)``, ``r ← r (1 − p_D) / (1 − r p_D)``, moments kept; detected by
   ``z_j``, ``w ← w r p_D N(z_j; H m, S)``, ``r ← 1``, Kalman (Joseph) update. Per measurement, the
   new track's local hypothesis from the Poisson part: ``w = λ_C c(z_j) + e(z_j)``,
   ``r = e / (λ_C c + e)`` (:meth:`PoissonIntensity.update`), or "no new object" (``w = 1``, ``r = 0``).
3. **Global hypotheses** (Theorem 2): a child of global hypothesis ``a`` assigns each measurement
   to exactly one track — a previous track's detection, or its own new track — and weighs
   ``W_a Π_i w_i``. Dividing every measurement's factor by its new-track weight ``ρ_j = λ_C c + e_j``
   makes this an assignment problem with **the tracks as rows** (row option 0: missed, always
   possible as ``r p_D < 1``) and the measurements as exclusive columns: score
   ``log(r p_D N(z_j; ·)) − log ρ_j``, constant ``log W_a + Σ_j log ρ_j`` — the form of
   :class:`~.AssociationProblem` the δ-GLMB preset uses (:mod:`.weights_glmb`), so the engine's child
   generators serve unchanged: Murty's k best (:class:`~.MurtyGenerator`) or the Gibbs sampler
   (:class:`~.GibbsGenerator`, distinct samples with exact weights), asked for ``ceil(H W_a)`` children of
   parent ``a`` (``allocation="proportional"``, as the 2018 paper's implementation) or for ``H``
   (``"exact"``: the ``H`` best children overall are among the ``H`` best of each parent, so Murty keeps
   the exact best). The generator sees only the coupled part of the problem: rows no return can take
   (gated out) are missed, returns no row can take start their new track, in every child.
4. **Pruning** (Sec. IV): the ``max_hypotheses`` heaviest children, those of normalised weight
   below ``hypothesis_threshold`` dropped; local hypotheses with ``r < existence_threshold`` removed
   from the global hypotheses (identical global hypotheses then merged, weights added); tracks absent
   from every global hypothesis deleted; Poisson components below ``poisson_threshold`` dropped.
5. **Estimates** (Sec. VI, "Estimator 1"): ``"best_hypothesis"`` reports the Bernoullis with
   ``r > existence_estimate`` (default 0.5) of the heaviest global hypothesis; ``"joint_map"`` maximises
   over global hypotheses **and** existence, ``W_a Π_i max(r_i, 1 − r_i)``, reporting the ``r > 0.5``
   Bernoullis of the winner — with an empty Poisson part and Bernoulli births this is the δ-GLMB's
   maximum-a-posteriori hypothesis.

**PMB** (``collapse="lbp"`` or ``"exact"``, Williams 2015's track-oriented marginal MB with a Poisson
part): the posterior after each update is collapsed to one multi-Bernoulli. With the association
marginals ``β_i(c)`` of the single global hypothesis's assignment problem — loopy belief propagation
(:func:`hypotrack.association.lbp.lbp_marginals`, Williams & Lau 2014) or exact enumeration — track ``i``
becomes ``r_i = Σ_c β_i(c) r_i(c)`` with the moment-matched mixture ``Σ_c β_i(c) r_i(c) N(m_i(c), P_i(c))``
of its single-target hypotheses, and measurement ``j``'s new track ``r = P(j unassigned) e_j / ρ_j``.
"""

from __future__ import annotations

import time as _clock
from dataclasses import dataclass, replace

import numpy as np

from .._logspace import logsumexp
from .._validation import (
    check_covariance,
    check_finite_array,
    check_finite_float,
    check_int,
    check_labels,
    check_measurements,
    check_nonnegative,
    check_positive,
    check_probability,
    check_seed,
    check_state_dimension,
)
from ..association.lbp import lbp_marginals
from ..gaussian import predict_with_unchecked, update_unchecked
from ..protocol import TrackEstimates
from .association_problem import AssociationProblem
from .generators import ChildGenerator, ExhaustiveGenerator, top_k
from .gibbs import GibbsGenerator
from .pmbm_poisson import PoissonIntensity, gaussian_loglik, moment_match
from .posterior import HypothesisEstimate
from .state import scan_interval

__all__ = ["PMBMFilter", "PMBMPosterior", "GlobalHypothesis", "ESTIMATORS", "COLLAPSES", "BIRTHS", "ALLOCATIONS"]

ESTIMATORS = ("best_hypothesis", "joint_map")
COLLAPSES = (None, "lbp", "exact")
BIRTHS = ("poisson", "bernoulli")
ALLOCATIONS = ("exact", "proportional")


@dataclass(frozen=True, eq=False)
class GlobalHypothesis:
    """One global hypothesis: its weight and the Bernoullis of the tracks present under it."""

    weight: float
    log_weight: float
    labels: np.ndarray
    existence: np.ndarray
    means: np.ndarray
    covs: np.ndarray

    @property
    def expected_number(self) -> float:
        return float(np.sum(self.existence))


@dataclass(frozen=True, eq=False)
class PMBMPosterior:
    """The multi-Bernoulli mixture (detected objects) and the Poisson part of a PMBM posterior.

    Attributes
    ----------
    log_weights : (H,) normalised log-weights of the global hypotheses, best first.
    cardinality : ``P(n)`` of the number of objects in the multi-Bernoulli mixture (the objects ever
        detected): the weights' mixture of each hypothesis's Poisson-binomial distribution.
    expected_number : ``Σ_n n P(n)`` of :attr:`cardinality`.
    undetected_mean : ``∫ λ^u``, the Poisson part's expected number of undetected objects.
    top : the heaviest global hypotheses (:class:`GlobalHypothesis`), best first.
    existence_threshold : the existence above which :attr:`map_estimate` reports a Bernoulli: the filter's
        ``existence_estimate`` (default 0.5), so the posterior's estimate is the filter's ``estimates()``.
    """

    log_weights: np.ndarray
    cardinality: np.ndarray
    expected_number: float
    undetected_mean: float
    top: tuple
    existence_threshold: float = 0.5

    @property
    def weights(self) -> np.ndarray:
        return np.exp(self.log_weights)

    @property
    def map_estimate(self) -> HypothesisEstimate:
        """The heaviest global hypothesis's Bernoullis with ``r >`` :attr:`existence_threshold` (the 2018 paper's
        estimator 1), in the form of the engine's :class:`~.posterior.HypothesisEstimate`."""
        h = self.top[0]
        on = h.existence > self.existence_threshold
        return HypothesisEstimate(h.weight, h.log_weight, h.labels[on], h.means[on], h.covs[on])


def poisson_binomial(r) -> np.ndarray:
    """``P(n)`` of the number of successes of independent Bernoullis with probabilities ``r``."""
    p = np.ones(1)
    for ri in np.asarray(r, dtype=float):
        p = np.concatenate([p * (1 - ri), [0.0]]) + np.concatenate([[0.0], p * ri])
    return p


class PMBMFilter:
    """PMBM filter (the 2018 paper) or, with ``collapse``, the PMB filter (Williams 2015); see the module docstring.

    Parameters
    ----------
    motion : motion model (``transition(x, dt)``, ``Q(dt)``).
    sensor : hypotrack.models.sensors.Sensor
        ``H``, ``R``; ``p_D`` in (0, 1) inside the field of view (0 outside, read at a component's mean);
        Poisson clutter, intensity ``λ_C c(z) = rate / area``.
    generator : ChildGenerator
        Murty or Gibbs (or exhaustive): the children of each global hypothesis.
    p_survive : float
        ``p_S`` in (0, 1], every object every scan.
    birth_means, birth_covs, birth_weights : array_like
        The birth terms: ``(B, d)``, ``(B, d, d)`` and weights ``(B,)``: Poisson birth intensity
        ``Σ_b w_b N(m_b, P_b)`` (``w_b ≥ 0``), or with ``birth="bernoulli"`` the existence ``r_B`` in (0, 1)
        of each labeled Bernoulli birth.
    birth : {"poisson", "bernoulli"}
    collapse : {None, "lbp", "exact"}
        ``None``: PMBM; otherwise PMB with these association marginals.
    max_hypotheses, hypothesis_threshold, existence_threshold, poisson_threshold
        Pruning (step 4): at most ``max_hypotheses`` (≥ 1) global hypotheses; thresholds in [0, 1).
    gate_probability : float, optional
        χ² validation gate in (0, 1) of every local hypothesis and Poisson component; ``None``: no gate.
    estimator : {"best_hypothesis", "joint_map"}
    existence_estimate : float
        ``"best_hypothesis"`` reports Bernoullis with ``r`` above it, in [0, 1).
    undetected_prior : float
        Expected number of objects not yet detected at :meth:`initialise`'s time, ≥ 0: a Poisson prior spread as
        the birth terms (in proportion to their weights), e.g. Williams 2015's scenario (3 objects at the start,
        0.005 born per scan, one birth density). 0: none.
    allocation : {"proportional", "exact"}
        Children asked of each global hypothesis ``a``: ``ceil(max_hypotheses W_a)`` (the default, as the 2018
        paper's implementation: light hypotheses get few children; a Gibbs generator also runs
        ``ceil(n_sweeps W_a)`` sweeps), or ``max_hypotheses`` (the kept ones are then the exact best of a k-best
        generator; about ten times the cost on a four-object scene).
    dt : float
        Default scan interval.
    seed : int or numpy.random.Generator
        Source of the Gibbs sampler's draws.
    """

    def __init__(self, motion, sensor, generator: ChildGenerator, *, p_survive=1.0, birth_means=None,
                 birth_covs=None, birth_weights=None, birth="poisson", collapse=None, max_hypotheses=100,
                 hypothesis_threshold=1e-4, existence_threshold=1e-5, poisson_threshold=1e-5, gate_probability=None,
                 estimator="best_hypothesis", existence_estimate=0.5, allocation="proportional", undetected_prior=0.0,
                 dt=1.0, seed=None):
        if not isinstance(generator, ChildGenerator):
            raise TypeError(f"generator must be a ChildGenerator, got {type(generator).__name__}")
        if getattr(sensor, "clutter", None) is None:
            raise ValueError("sensor.clutter must be a PoissonClutter: the PMBM update needs the clutter intensity")
        self.p_D = check_probability(sensor.detection.p_D, "p_D", low_open=True, high_open=True)
        self.motion, self.sensor, self.generator = motion, sensor, generator
        if not getattr(sensor.measurement, "linear", True):
            raise ValueError("sensor.measurement must be linear (H, R) for the PMBM filters; a nonlinear model (the "
                             "radar's sensor frame) runs on HypothesisFilter, the factored engine, GNN and JPDA")
        self.H = check_finite_array(sensor.measurement.H, "sensor H", ndim=2)
        self.R = check_covariance(sensor.measurement.R, "sensor R", dim=self.H.shape[0])
        d = self.H.shape[1]
        check_state_dimension(motion, d, f"the sensor (H of shape {self.H.shape})")
        self.clutter_intensity = check_positive(sensor.clutter.rate / sensor.clutter.region.area,
                                                "clutter intensity (rate / area)")
        self.p_survive = check_probability(p_survive, "p_survive", low_open=True)
        if birth not in BIRTHS:
            raise ValueError(f"birth must be one of {BIRTHS}, got {birth!r}")
        if collapse not in COLLAPSES:
            raise ValueError(f"collapse must be one of {COLLAPSES}, got {collapse!r}")
        if estimator not in ESTIMATORS:
            raise ValueError(f"estimator must be one of {ESTIMATORS}, got {estimator!r}")
        if allocation not in ALLOCATIONS:
            raise ValueError(f"allocation must be one of {ALLOCATIONS}, got {allocation!r}")
        self.birth, self.collapse, self.estimator, self.allocation = birth, collapse, estimator, allocation
        n_b = 0 if birth_weights is None else len(np.atleast_1d(birth_weights))
        if birth == "bernoulli":
            for r in np.atleast_1d(birth_weights) if n_b else ():
                check_probability(r, "birth existence r_B", low_open=True, high_open=True)
        self.birth_intensity = PoissonIntensity.from_weights(
            np.zeros(0) if birth_weights is None else birth_weights,
            np.zeros((0, d)) if birth_means is None else birth_means,
            np.zeros((0, d, d)) if birth_covs is None else birth_covs, d)
        self.max_hypotheses = check_int(max_hypotheses, "max_hypotheses", minimum=1)
        for name, v in (("hypothesis_threshold", hypothesis_threshold), ("existence_threshold", existence_threshold),
                        ("poisson_threshold", poisson_threshold), ("existence_estimate", existence_estimate)):
            if not (check_nonnegative(v, name) < 1):
                raise ValueError(f"{name} must lie in [0, 1), got {v!r}")
        self.hypothesis_threshold, self.existence_threshold = float(hypothesis_threshold), float(existence_threshold)
        self.poisson_threshold, self.existence_estimate = float(poisson_threshold), float(existence_estimate)
        self.gate_probability = (None if gate_probability is None else
                                 check_probability(gate_probability, "gate_probability", low_open=True, high_open=True))
        self.undetected_prior = check_nonnegative(undetected_prior, "undetected_prior")
        if self.undetected_prior > 0 and not len(self.birth_intensity):
            raise ValueError("undetected_prior > 0 needs birth terms: the undetected objects are spread as the births")
        self.dt = check_positive(dt, "dt")
        self.rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(check_seed(seed))
        self.last_stats = {}
        self.initialise(np.zeros((0, d)))

    # ------------------------------------------------------------------ state
    def initialise(self, means, covs=None, labels=None, *, time: float = 0.0, undetected=None):
        """Known objects as Bernoullis with ``r = 1`` in one global hypothesis of weight 1 (``n = 0``
        allowed), valid at ``time``; ``undetected``: an initial Poisson part (:class:`PoissonIntensity`;
        default: ``undetected_prior`` expected objects spread as the birth terms, none when it is 0)."""
        d = self.H.shape[1]
        means = np.asarray(means, dtype=float)
        means = np.zeros((0, d)) if means.size == 0 else check_finite_array(np.atleast_2d(means), "means",
                                                                            shape=(None, d))
        n = len(means)
        covs = np.zeros((0, d, d)) if n == 0 else check_covariance(np.asarray(covs, dtype=float).reshape(n, d, d),
                                                                     "covs", dim=d, batched=True)
        self.labels = np.arange(n, dtype=np.int64) if labels is None else check_labels(labels, n)
        self.r, self.means, self.covs = np.ones(n), means.copy(), covs.copy()
        self.last_return = np.full(n, -1, np.int64)
        self.last_prediction = (means.copy(), covs.copy())
        self.track_of = np.arange(n, dtype=np.int64)  # track of each local hypothesis
        self.assign = np.arange(n, dtype=np.int64)[None, :]  # (H, T): local hypothesis per track, -1 absent
        self.log_w = np.zeros(1)
        if undetected is not None and not isinstance(undetected, PoissonIntensity):
            raise TypeError(f"undetected must be a PoissonIntensity, got {type(undetected).__name__}")
        if undetected is None:
            b = self.birth_intensity
            undetected = PoissonIntensity.empty(d) if self.undetected_prior == 0 else PoissonIntensity(
                b.log_w - logsumexp(b.log_w) + np.log(self.undetected_prior), b.means, b.covs)
        self.undetected = undetected
        self.next_label = int(self.labels.max()) + 1 if n else 0
        self.time = check_finite_float(time, "time")
        self.scan_index = 0

    # ------------------------------------------------------------------ recursion
    _STATE = ("r", "means", "covs", "track_of", "assign", "log_w", "labels", "undetected", "next_label", "time",
              "scan_index", "last_stats", "last_return", "last_prediction")

    def step(self, Z, time=None, *, dt=None):
        """Predict to ``time`` (or by ``dt``, or the default interval) and update with returns ``Z`` (m, p).
        All-or-nothing: on an error the filter is as before. Returns :meth:`posterior`."""
        saved = ({name: getattr(self, name) for name in self._STATE}, self.rng.bit_generator.state)
        try:
            t0 = _clock.perf_counter()
            interval, now = scan_interval(self.time, time, dt, self.dt)
            Z = check_measurements(Z, "Z", self.H.shape[0])
            self._predict(interval)
            self._update(Z)
            self.time, self.scan_index = now, self.scan_index + 1
            self.last_stats["time_total"] = _clock.perf_counter() - t0
        except BaseException:
            for name, value in saved[0].items():
                setattr(self, name, value)  # a step replaces these arrays, never writes into them
            self.rng.bit_generator.state = saved[1]
            raise
        return self.posterior()

    def _predict(self, interval):
        """Step 1 (Theorem 1)."""
        log_ps = np.log(self.p_survive)
        if self.birth == "poisson":
            self.undetected = self.undetected.predict(self.motion, interval, log_ps, self.birth_intensity)
        else:
            self.undetected = self.undetected.predict(self.motion, interval, log_ps,
                                                      PoissonIntensity.empty(self.H.shape[1]))
        if len(self.r) and interval > 0:
            self.means, self.covs = predict_with_unchecked(self.motion, self.means, self.covs, interval)
        self.r = self.r * self.p_survive
        if self.birth == "bernoulli" and len(self.birth_intensity):
            b = self.birth_intensity
            n_l, n_t, n_b = len(self.r), self.assign.shape[1], len(b)
            self.r = np.concatenate([self.r, np.exp(b.log_w)])
            self.means, self.covs = np.concatenate([self.means, b.means]), np.concatenate([self.covs, b.covs])
            self.track_of = np.concatenate([self.track_of, n_t + np.arange(n_b)])
            new_cols = np.broadcast_to(n_l + np.arange(n_b), (len(self.log_w), n_b))
            self.assign = np.hstack([self.assign, new_cols])
            self.labels = np.concatenate([self.labels, self.next_label + np.arange(n_b)])
            self.next_label += n_b

    def _p_detect(self, means):
        if len(means) == 0:
            return np.zeros(0)
        return np.where(self.sensor.in_view(means), self.p_D, 0.0)

    def single_target_hypotheses(self, Z):
        """Step 2 for the predicted local hypotheses and returns ``Z``: ``(log_miss, r_miss, log_det)`` with
        ``log_det`` (L, m) ``log(r p_D N(z_j; H m, S))`` (``-inf`` gated out), and the Poisson terms of
        :meth:`PoissonIntensity.update`."""
        pd = self._p_detect(self.means)
        rp = self.r * pd
        log_miss = np.log1p(-rp)
        with np.errstate(divide="ignore", invalid="ignore"):
            r_miss = np.where(rp < 1, self.r * (1 - pd) / (1 - rp), 0.0)
            log_det = (np.log(rp)[:, None] + gaussian_loglik(Z, self.means, self.covs, self.H, self.R,
                                                             self.gate_probability).T)
        poisson = self.undetected.update(Z, self.H, self.R, self._p_detect(self.undetected.means),
                                         self.clutter_intensity, self.gate_probability)
        return log_miss, r_miss, log_det.reshape(len(self.r), len(Z)), poisson

    def association_problem(self, a: int, log_miss, log_det, log_rho) -> tuple[np.ndarray, AssociationProblem]:
        """Step 3: the local hypotheses of the tracks present in global hypothesis ``a`` and their
        assignment problem (rows = those local hypotheses, columns = the returns)."""
        rows = self.assign[a][self.assign[a] >= 0]
        m = len(log_rho)
        return rows, AssociationProblem(
            target_scores=log_det[rows] - log_rho[None, :], option_scores=log_miss[rows][:, None], n_objects=m,
            count_term=np.zeros((m + 1, 1)), constant=float(self.log_w[a] + np.sum(log_rho)))

    def _generate(self, problem: AssociationProblem, share: float = 1.0):
        """The generator's best ``ceil(share max_hypotheses)`` children of ``problem`` (a sampler's sweeps scaled
        by ``share`` too), run on its coupled part only: a row no return can be
        assigned to (gated out) is missed in every child, a return no row can take starts its new track in
        every child; their scores enter the constant (the 2018 paper's implementation trims its cost
        matrix the same way). Returns events over all rows and exact log-weights."""
        T = problem.target_scores
        rows = np.flatnonzero(np.isfinite(T).any(axis=1))
        cols = np.flatnonzero(np.isfinite(T[rows]).any(axis=0))
        n = problem.n_returns
        if len(rows) == 0:
            return np.full((1, n), -1, np.int32), np.array([problem.constant + problem.option_scores[:, 0].sum()])
        fixed = np.setdiff1d(np.arange(n), rows)
        sub = AssociationProblem(target_scores=T[np.ix_(rows, cols)], option_scores=problem.option_scores[rows],
                                 n_objects=len(cols), count_term=np.zeros((len(cols) + 1, 1)),
                                 constant=problem.constant + problem.option_scores[fixed, 0].sum())
        generator = self.generator
        if share < 1.0 and isinstance(generator, GibbsGenerator):
            generator = replace(generator, n_sweeps=int(np.ceil(generator.n_sweeps * share)))
        ev, w = generator.generate(sub, self.rng, keep=int(np.ceil(self.max_hypotheses * share)))
        full = np.full((len(w), n), -1, np.int64)
        ev = np.asarray(ev, dtype=np.int64)
        full[:, rows] = np.where(ev >= 0, cols[np.maximum(ev, 0)], ev)
        return full, np.asarray(w, dtype=float)

    def _update(self, Z):
        log_miss, r_miss, log_det, (undetected, log_e, log_rho, new_means, new_covs) = self.single_target_hypotheses(Z)
        parents, events, lw = [], [], []
        n_gen = 0
        for a in range(len(self.log_w)):
            rows, problem = self.association_problem(a, log_miss, log_det, log_rho)
            if self.collapse is not None:
                self._collapse(Z, rows, problem, r_miss, log_e, log_rho, new_means, new_covs, undetected)
                return
            share = 1.0 if self.allocation == "exact" else float(np.exp(self.log_w[a]))
            ev, w = self._generate(problem, share)
            n_gen += len(w)
            full = np.full((len(w), self.assign.shape[1]), -2, np.int64)  # -2: track absent; -1 missed; j
            present = np.flatnonzero(self.assign[a] >= 0)
            full[:, present] = ev
            parents.append(np.full(len(w), a))
            events.append(full)
            lw.append(np.asarray(w, dtype=float))
        parents, events, lw = np.concatenate(parents), np.vstack(events), np.concatenate(lw)
        ok = np.isfinite(lw)
        parents, events, lw = parents[ok], events[ok], lw[ok]
        if len(lw) == 0:
            raise RuntimeError("no global hypothesis has a positive weight")
        log_total = logsumexp(lw)
        sel = top_k(lw, self.max_hypotheses)
        if self.hypothesis_threshold > 0:
            sel = sel[lw[sel] - logsumexp(lw[sel]) >= np.log(self.hypothesis_threshold)]
        parents, events, lw = parents[sel], events[sel], lw[sel]
        self.last_stats = {"n_children": n_gen, "n_kept": len(lw), "mass_retained": float(np.exp(logsumexp(lw) - log_total))}
        self._materialise(Z, parents, events, lw, r_miss, log_e, log_rho, new_means, new_covs, undetected)

    def _materialise(self, Z, parents, events, lw, r_miss, log_e, log_rho, new_means, new_covs, undetected):
        """The new tracks, local hypotheses and global hypotheses from the kept children (step 3–4)."""
        m, T = len(Z), self.assign.shape[1]
        old_local = np.where(events >= -1, self.assign[parents], -1)  # (K, T) predicted local hypothesis
        pairs = {}
        for k in range(len(lw)):
            for i in np.flatnonzero(events[k] >= -1):
                pairs.setdefault((int(old_local[k, i]), int(events[k, i])), len(pairs))
        src = np.array([p[0] for p in pairs], dtype=np.int64).reshape(-1)
        ret = np.array([p[1] for p in pairs], dtype=np.int64).reshape(-1)
        means, covs = self.means[src].copy(), self.covs[src].copy()
        nan = np.full((m, *means.shape[1:]), np.nan)
        self.last_prediction = (np.concatenate([means, nan]), np.concatenate([covs, np.full((m, *covs.shape[1:]), np.nan)]))
        self.last_return = np.concatenate([ret, np.arange(m)])
        r = np.where(ret >= 0, 1.0, r_miss[src])
        hit = ret >= 0
        if hit.any():
            means[hit], covs[hit] = update_unchecked(means[hit], covs[hit], Z[ret[hit]], self.H, self.R)
        new_assign = np.full((len(lw), T + m), -1, np.int64)
        for k in range(len(lw)):
            for i in np.flatnonzero(events[k] >= -1):
                new_assign[k, i] = pairs[(int(old_local[k, i]), int(events[k, i]))]
        # measurement j's new track: present (its one local hypothesis, index L + j) where j is unassigned
        L = len(pairs)
        used = np.zeros((len(lw), m), bool)
        rows, cols = np.nonzero(events >= 0)
        used[rows, events[rows, cols]] = True
        has_e = np.isfinite(log_e)
        new_assign[:, T:] = np.where(~used & has_e[None, :], L + np.arange(m)[None, :], -1)
        r_new = np.exp(log_e - log_rho)
        self.r = np.concatenate([r, r_new])
        self.means, self.covs = np.concatenate([means, new_means]), np.concatenate([covs, new_covs])
        self.track_of = np.concatenate([self.track_of[src], T + np.arange(m)])
        self.labels = np.concatenate([self.labels, self.next_label + np.arange(m)])
        self.next_label += m
        self.assign, self.log_w = new_assign, lw - logsumexp(lw)
        self.undetected = undetected.pruned(self.poisson_threshold)
        self._prune()

    def _prune(self):
        """Step 4: Bernoullis below ``existence_threshold`` leave the global hypotheses; identical global
        hypotheses are merged; unused local hypotheses and empty tracks are deleted, labels kept."""
        A = self.assign.copy()
        if len(self.r):
            low = self.r < self.existence_threshold if self.existence_threshold > 0 else self.r <= 0
            A[(A >= 0) & low[np.maximum(A, 0)]] = -1
        if len(A):
            uniq, inverse = np.unique(A, axis=0, return_inverse=True)
            inverse = np.asarray(inverse).reshape(-1)
            if len(uniq) < len(A):
                lw = np.array([logsumexp(self.log_w[inverse == u]) for u in range(len(uniq))])
                order = np.argsort(-lw, kind="stable")
                A, self.log_w = uniq[order], lw[order]
        keep_tracks = np.flatnonzero((A >= 0).any(axis=0))
        A = A[:, keep_tracks]
        used = np.unique(A[A >= 0])
        remap = np.full(len(self.r), -1, np.int64)
        remap[used] = np.arange(len(used))
        self.assign = np.where(A >= 0, remap[np.maximum(A, 0)], -1)
        track_remap = np.full(len(self.labels), -1, np.int64)
        track_remap[keep_tracks] = np.arange(len(keep_tracks))
        self.r, self.means, self.covs = self.r[used], self.means[used], self.covs[used]
        self.last_return = self.last_return[used]
        self.last_prediction = tuple(a[used] for a in self.last_prediction)
        self.track_of = track_remap[self.track_of[used]]
        self.labels = self.labels[keep_tracks]

    def _collapse(self, Z, rows, problem, r_miss, log_e, log_rho, new_means, new_covs, undetected):
        """PMB (Williams 2015): the single global hypothesis's update collapsed to one multi-Bernoulli."""
        m, n = len(Z), len(rows)
        beta = self.association_marginals(problem) if n else np.zeros((0, m + 1))
        p_unassigned = np.clip(1.0 - beta[:, 1:].sum(axis=0), 0.0, 1.0)
        r_out, means, covs = np.zeros(n), np.zeros((n, self.H.shape[1])), np.zeros((n, *self.covs.shape[1:]))
        for i, l in enumerate(rows):
            det = np.flatnonzero(beta[i, 1:] > 0)
            comp_w = np.concatenate([[beta[i, 0] * r_miss[l]], beta[i, 1 + det]])
            x, P = update_unchecked(np.repeat(self.means[l][None], len(det), 0),
                                    np.repeat(self.covs[l][None], len(det), 0), Z[det], self.H, self.R)
            comp_m, comp_P = np.concatenate([self.means[l][None], x]), np.concatenate([self.covs[l][None], P])
            r_out[i] = comp_w.sum()
            if r_out[i] > 0:
                with np.errstate(divide="ignore"):
                    means[i], covs[i] = moment_match(np.log(comp_w), comp_m, comp_P)
            else:
                means[i], covs[i] = self.means[l], self.covs[l]
        r_new = p_unassigned * np.exp(log_e - log_rho)
        T = self.assign.shape[1]
        # a collapsed Bernoulli mixes its returns: no single return updated it (-1), its prediction is its prior
        self.last_return = np.concatenate([np.full(n, -1, np.int64), np.arange(m)])
        self.last_prediction = (np.concatenate([self.means[rows], np.full((m, *self.means.shape[1:]), np.nan)]),
                                np.concatenate([self.covs[rows], np.full((m, *self.covs.shape[1:]), np.nan)]))
        self.r = np.concatenate([r_out, r_new])
        self.means, self.covs = np.concatenate([means, new_means]), np.concatenate([covs, new_covs])
        self.track_of = np.concatenate([self.track_of[rows], T + np.arange(m)])
        self.labels = np.concatenate([self.labels, self.next_label + np.arange(m)])
        self.next_label += m
        A = np.full((1, T + m), -1, np.int64)
        A[0, self.track_of] = np.arange(n + m)
        self.assign, self.log_w = A, np.zeros(1)
        self.undetected = undetected.pruned(self.poisson_threshold)
        self.last_stats = {"n_children": 1, "n_kept": 1, "mass_retained": 1.0}
        self._prune()

    def association_marginals(self, problem: AssociationProblem) -> np.ndarray:
        """``β`` (n, m + 1): column 0 missed, column ``1 + j`` return ``j``, of the tracks (rows) of ``problem``:
        loopy belief propagation (``collapse="lbp"``) or the exact sum over every association."""
        if self.collapse == "lbp":
            weights = np.hstack([problem.option_scores[:, :1], problem.target_scores])
            return lbp_marginals(weights).beta
        events, lw = ExhaustiveGenerator().generate(problem)
        w = np.exp(lw - logsumexp(lw))
        beta = np.zeros((problem.n_returns, problem.n_exclusive + 1))
        for c in range(-1, problem.n_exclusive):
            beta[:, c + 1] = (events == c).T @ w
        return beta

    # ------------------------------------------------------------------ output
    def global_hypotheses(self) -> list[GlobalHypothesis]:
        """Every global hypothesis (heaviest first) with the Bernoullis present under it."""
        order = np.argsort(-self.log_w, kind="stable")
        out = []
        for a in order:
            loc = self.assign[a][self.assign[a] >= 0]
            out.append(GlobalHypothesis(float(np.exp(self.log_w[a])), float(self.log_w[a]),
                                        self.labels[self.track_of[loc]], self.r[loc], self.means[loc], self.covs[loc]))
        return out

    def posterior(self, n_top: int = 10) -> PMBMPosterior:
        """The global hypotheses' weights, the multi-Bernoulli mixture's cardinality and the best ``n_top``."""
        hyps = self.global_hypotheses()
        card = np.zeros(1)
        for h in hyps:
            p = h.weight * poisson_binomial(h.existence)
            card = np.pad(card, (0, max(0, len(p) - len(card)))) + np.pad(p, (0, max(0, len(card) - len(p))))
        lw = np.array([h.log_weight for h in hyps])
        return PMBMPosterior(lw, card, float(np.arange(len(card)) @ card), self.undetected.total,
                             tuple(hyps[:n_top]), self.existence_estimate)

    def estimated_local_hypotheses(self) -> np.ndarray:
        """Indices of the local hypotheses :meth:`estimates` reports, in its order (module docstring, step 5):
        with :attr:`last_return` (the return that updated each at the last scan: ``j``; -1 none: missed, or a
        PMB Bernoulli mixing several) and :attr:`last_prediction` (its predicted mean and covariance; NaN for a
        track the last scan's return ``j`` started from the Poisson part), an adapter can name each estimate's
        return and prediction."""
        order = np.argsort(-self.log_w, kind="stable")
        if self.estimator == "best_hypothesis":
            a, threshold = order[0], self.existence_estimate
        else:
            with np.errstate(divide="ignore"):
                score = [self.log_w[a] + np.sum(np.log(np.maximum(self.r[loc], 1 - self.r[loc])))
                         for a in order for loc in [self.assign[a][self.assign[a] >= 0]]]
            a, threshold = order[int(np.argmax(score))], 0.5
        loc = self.assign[a][self.assign[a] >= 0]
        return loc[self.r[loc] > threshold]

    def estimates(self) -> TrackEstimates:
        """The Bernoullis of the estimator's global hypothesis (module docstring, step 5)."""
        loc = self.estimated_local_hypotheses()
        return TrackEstimates(self.time, self.labels[self.track_of[loc]], self.means[loc], self.covs[loc])
