"""The factored hypothesis engine: the posterior as a product of independent groups.

:class:`~.filter.HypothesisFilter` keeps *global* hypotheses: every parent's association problem
spans every object and every return, so the number of hypotheses — and the work per scan —
grows with the product of the ambiguities anywhere in view, although two objects whose gates
never share a return do not influence each other's weights. :class:`FactoredFilter` keeps the
posterior as a product of *groups* (Beard, Vo & Vo, "A solution for large-scale multi-object
tracking", IEEE TSP 68, 2020): each group is a hypothesis set over its own objects, run by the
engine's own machinery (any weight model × child generator × population, the same children,
duplicate merging, cap and Kalman updates), and a scan touches a group only through the
returns in its gate.

One ``step(Z)``
---------------
1. Predict every group's tracks (with ``lazy``, of the singletons only those that may be in
   view); score every return against them (the engine's
   :meth:`~..filter.HypothesisFilter.track_scores`, each (return, track) pair once; at scale only the pairs a
   k-d tree over the returns finds near each track, with the same numbers, :mod:`.scores`). A group's
   *gate* is the set of returns inside the validation gate of any of its tracks, in any of its
   hypotheses (the engine's ``allowed``; the field of view enters through ``p_D``, not the gate,
   unless ``gate_out_of_view=False``, when a track out of view gates nothing).
2. Build the bipartite graph groups/singletons/birth terms — returns (components by
   :func:`scipy.sparse.csgraph.connected_components`; only the components a return or birth term
   reaches are visited in Python): a group is linked to the returns in
   its gate, a birth term (or birth region) to the returns it could be the first detection of
   (finite birth likelihood; see ``births``), and with HOMHT's seeded births each return in no
   gate becomes a node of its own (a new object or clutter). Its connected components are this
   scan's problems: groups in one component are **merged** (the product of their hypotheses,
   capped at ``H∞`` as the engine caps, :func:`~..factored_groups.product`), receive the
   component's returns and birth terms, and take one engine step. A birth term linked to no
   return still forms a group (a birth that is not detected). Returns linked to nothing are
   clutter for every hypothesis: a common factor, dropped.
3. A group with no return and no birth term only predicts when that is exact (no population
   events and the same ``Π (1 − p_D)`` in all its hypotheses); otherwise it takes the engine's
   step on an empty scan (deaths, survival and missed detections change its weights).
4. **Split**: the objects of each group are partitioned by this scan's interaction (objects
   linked through a shared gated return, a newborn object with its birth term or return); if
   there are several parts the joint is compared with the product of its marginals
   (:func:`~..factored_groups.factorise`). ``split="marginal"`` (Beard et al.'s method) splits
   always, exactly when the joint factorises and otherwise with the marginal-product
   approximation, whose KL and L1 losses are recorded (:attr:`split_records`, ``last_stats``);
   ``split="exact"`` splits off each part that is exactly independent of the rest of its group
   (one two-way check per part) and keeps the others together; ``split="never"`` keeps groups
   merged. Every group is then pruned at ``min_weight``: a step leaves without moments the new
   tracks its kept hypotheses hold with less than ``min(min_weight, 1/H∞)`` in all, which no
   hypothesis the pruning keeps can hold (:func:`~..children.heavy_entries`; bit for bit the same
   posterior, ``tests/unit/hypotheses/factored/test_light_entries.py``).

Singletons and lazy prediction
------------------------------
At catalogue scale nearly every group is a *singleton*: one object, one hypothesis, one track
(an object nothing has disturbed). With a population that can take no event in a quiet group
(:func:`.lane.silent`: none, or labeled multi-Bernoulli / binomial with ``p_S = 1``) a singleton is
exactly its Gaussian, so the filter keeps all singletons in one batched *lane* (means,
covariances, labels, the time each was last predicted to) instead of one Python object each;
a scan costs Python work only for the groups and singletons a return or birth term reaches,
and a step's results that are singletons go back to the lane. The lane changes no number.
With ``lazy=True`` a singleton is predicted only when it may be observed: each scan the lane's
means at the last scan (not covariances) are advanced by one scan interval, and only the singletons whose
predicted position is inside the sensor's field of view (``p_D > 0``) are predicted in full
(mean and covariance, over the whole gap since their last prediction) and scored. A track out
of view can take no return, so this changes the posterior only through the process noise: one
EKF prediction over a gap of ``k`` scans adds ``Q(kΔ)`` where ``k`` predictions add
``Σ Φ Q(Δ) Φᵀ`` (equal for a linear constant-velocity model, a few per cent apart on an
orbit over minutes, but not over an orbit's gap between passes: the white-acceleration ``Q(kΔ)`` is
isotropic where the orbit shears the accumulated noise along the track — for a 850-km orbit with
``q = 1e-9`` km²/s³ over 65 min the one prediction's in-track σ is 11 km for 17 km and its cross-track
4.4 km for 1.4 km, over 95 min 15 km for 31 km and 7.9 km for 1.8 km, enough to swap the labels of
fragments 20 km apart at re-acquisition; ``tests/unit/hypotheses/factored/test_lazy_gap.py``). The means are exact either way for the Kepler model; a numerically integrated
one (``J2Orbit3D``) advances the lane's means scan by scan and a candidate's over its whole gap, equal
up to its integration error.
The same holds for a multi-hypothesis group (an object whose existence or association is still
open) whose tracks are all out of view: it is left as it was, its means advanced a scan at a time
in the same batch, and predicted over its whole gap when one of its tracks may be seen again. At
catalogue scale these groups accumulate out of view (nothing resolves them there) and would otherwise
be predicted and visited every scan. :attr:`~FactoredFilter.posterior` and
:attr:`~FactoredFilter.groups` predict the lazy singletons and groups to the current scan (:mod:`.lane`).
With per-track survival (a labeled multi-Bernoulli population with ``p_S = 1`` and a ``survival``
callable, e.g. :class:`~..population_lmb.UnconfirmedDecay`) the lane holds the singletons whose track
surely survives (``p_S = 1``: no "died" child, so the singleton is again exactly its Gaussian); a candidate
whose predicted ``p_S`` is below 1 takes its step on the empty scan and leaves the lane, and the groups are
predicted every scan (:func:`.lane.survival_lane`, which states what lazy prediction assumes there).
With ``bernoulli_lane`` (any labeled multi-Bernoulli or binomial population whose tracks may die) the lane holds every
lone track as a Bernoulli instead: its existence ``r`` beside its moments, ``r ← p_S r`` a scan out of view,
``r ← r p_S (1 − p_D) / (1 − r p_S p_D)`` a scan in view with no return for it, and the engine's own two
hypotheses (exists / not) when a return or birth term reaches it — the general engine's posterior
(:mod:`.lane`, "Bernoulli singletons"; ``tests/unit/hypotheses/factored/test_bernoulli_lane.py``), at the cost of
the lane.

The fast path
-------------
With ``fast_path=True`` (off by default) the components whose engine step is known in closed form
are not stepped one by one (:mod:`.fast_path`): a *lone track* — one singleton of the lane with one
return nothing else gates — whose alternatives (missed, the return clutter or a seeded birth) all
fall below ``min_weight`` is Kalman-updated (Joseph form) in one batch with the others and goes
back to the lane; returns no gate reaches and birth terms no return reaches, whose steps keep no
object, are dropped. The decision is taken from the weight models' closed forms with a margin, the
results go where the general path puts them (plan order), the other steps draw the same random
streams and the labels the skipped steps would have used are counted; with the engine's
``validity`` test every child's tracks are tested as the general step tests them. Two more closed
forms (without a validity test): a quiet group of one object whose empty-scan step would leave no
object after the pruning (an undetected newborn fading out) is dropped without a step, and a lone
birth term whose two children are both kept is stepped from one engine step of such a term of its
``r_B`` (the same hypotheses and weights; the term's prior as the born track). Reid's births seeded as a
mixture (one child per component, HOMHT's admissible regions) have their lone tracks' closed form in
:mod:`.fast_mixture`, and a quiet group of one-track hypotheses under per-track deaths takes its empty-scan
step in closed form (:mod:`.sleeping`), and a birth term whose one return no track competes for, born
detected with it alone after the pruning, has the closed form of :mod:`.born_detected`; a return in no gate under
HOMHT's mixture seeded births (clutter or a newborn in one of its admissible-region components) has that of
:mod:`.seeded_birth`, the scan's lone returns' covariances mapped in one call. The posterior is the general path's, bit for bit (to 1e-12 with the
radar's sensor-frame EKF, whose batches round differently: ``tests/unit/hypotheses/factored/test_fast_path.py``,
``test_fast_path_catalogue.py``, ``test_fast_mixture.py``, ``test_sleeping.py``, ``test_born_detected.py``,
``test_seeded_birth.py``). ``last_stats`` counts ``n_fast_path`` (lone tracks), ``n_fast_births``, ``n_fast_clutter``,
``n_fast_quiet``, ``n_fast_born``, ``n_fast_born_detected`` and ``n_fast_seeded``.

When the factored posterior equals the unfactored one
-----------------------------------------------------
The joint children of a product of groups are the products of the groups' children exactly
when each child's weight is a product of per-group factors and no return is open to two
groups — the second holds by construction, the first is a property of the model:

* **separable** (exact, tested in ``tests/crosscheck/test_equivalence_factored.py``): the δ-GLMB
  weights with the labeled multi-Bernoulli population (Vo, Vo & Hoang 2017: ``Π_i η_i(γ_i)``;
  each birth term is given to one group per scan), and Reid's HOMHT with a fixed number of
  objects or Poisson births seeded at returns (document 001 Eq. 30, 35: a product over returns and
  objects), and FISST with Poisson clutter (document 001 Eq. 6–7); all as long as no cap binds
  (each group keeps ``H∞`` hypotheses, so the factored filter keeps more joint hypotheses than
  the unfactored one) and every split was exact. A split after a real interaction is never
  exact: the joint lacks the configurations where both groups took the shared return.
* **not separable** (the factored filter is a different approximation): H-FISST's count term
  ``−log(m!/(m − n)!)`` (document 000 Eq. 8) counts the returns of the whole scan, and a group sees
  its own; document 001's binomial population allows one silent event per child, i.e. per group
  here; document 000's **single-event** population (one birth or one death per scan for the whole
  scene, Eq. 30) couples every object through ``P(no event) = 1 − M_b α − M_d β``. The factored
  engine applies the event model **per group** — one event per group and scan, ``M_d`` the
  group's objects in view — which changes the prior: with ``G`` groups up to ``G`` events
  per scan can happen, and no-event children weigh ``1 − M_b α − M_d,g β`` per group instead
  of ``1 − M_b α − M_d β`` overall. :func:`cardinality_total_variation` (:mod:`.summary`) measures the effect;
  the test reports it on a small scene.

Where each job lives
--------------------
:mod:`.options` (:class:`FactoredOptions`, every option stated and checked once), :mod:`.engine`
(:class:`FactoredFilter`: the scan in named stages), :mod:`.planner` (the graph, the plans, the
splits), :mod:`.scores` (the returns against the predicted tracks: dense, or at scale the gated pairs
through a k-d tree), :mod:`.fast_path` (the lone tracks' batch), :mod:`.lane` (singletons and lazy prediction), :mod:`.pool` (the engine steps and the
workers that run them), :mod:`.summary` (:class:`FactoredPosterior`), :mod:`.multisensor` (the scans of several
sensors, each with its sensor's engine; birth terms for the scan they belong to), :mod:`.births_kernels` (the birth terms' gate test in one compiled pass); the measurement-driven birth
model :class:`AdaptiveBirth` lives beside the populations (:mod:`..population_adaptive`), Murty's k best of a
one-return problem in :mod:`..one_return`, and the loading of the engine's compiled kernels before a timed loop
in :mod:`..warm_factored`.
"""

from ..population_adaptive import AdaptiveBirth
from .engine import FactoredFilter, FactoredState
from .lane import predict_each as _predict_each  # noqa: F401 (the name callers used before the split)
from .options import SPLITS  # noqa: F401
from .options import FactoredOptions
from .summary import FactoredPosterior, cardinality_total_variation

__all__ = ["AdaptiveBirth", "FactoredFilter", "FactoredOptions", "FactoredPosterior", "FactoredState",
           "cardinality_total_variation"]
