"""How sure the factored posterior is of its MAP's tracks: :func:`map_track_marginals`, :func:`map_label_marginals`.

The factored engine keeps a group's hypotheses as index arrays into one track store, and a store entry is one
association history (the engine's next store holds the *distinct* ``(track, return)`` pairs of the surviving
children, :meth:`~..filter.HypothesisFilter._materialise`, recursively from the scan's first store). So the
posterior probability that the MAP hypothesis's track ``i`` of label ``ℓ`` is the right one — that object ``ℓ``
has exactly this association history — is the total weight of the hypotheses holding entry ``i``:

    ``P(i) = Σ_h w_h [i ∈ I_h]``,  ``w_h = exp(log w_h − logsumexp(log w))``

(the marginal of a δ-GLMB/HOMHT posterior over the track ``(ℓ, history)``, Vo & Vo 2013 Eq. 17 summed over the
hypotheses ``I_h`` containing it). A hypothesis that gives label ``ℓ`` another track (the two neighbours' labels
swapped) or no track (``ℓ`` dead or not born) adds nothing. A singleton of the lane is one hypothesis: ``P = 1``.
"""

from __future__ import annotations

import numpy as np

from ..._logspace import logsumexp

__all__ = ["map_track_marginals", "map_label_marginals"]


def map_track_marginals(log_w, tracks) -> tuple[int, np.ndarray]:
    """``(h*, P)`` of one group: ``h*`` its MAP hypothesis (the first of largest weight, as
    :func:`~..posterior.summarise`) and, per track of ``tracks[h*]`` in its order, the total normalised weight of the
    hypotheses holding the same store entry (module docstring). ``log_w``: ``(H,)`` log-weights (normalised or not);
    ``tracks``: per hypothesis, its distinct store indices."""
    lw = np.asarray(log_w, dtype=float)
    if lw.ndim != 1 or len(lw) == 0 or len(tracks) != len(lw):
        raise ValueError(f"log_w must be a non-empty (H,) array with one track list per hypothesis, got {lw.shape} "
                         f"and {len(tracks)} track lists")
    if not np.all(np.isfinite(lw) | (lw == -np.inf)) or not np.isfinite(lw.max()):
        raise ValueError("log_w must be finite or -inf, with at least one finite entry")
    w = np.exp(lw - logsumexp(lw))
    lists = [np.asarray(t, dtype=np.int64) for t in tracks]
    h = int(np.argmax(lw))
    if not lists[h].size:
        return h, np.zeros(0)
    idx = np.concatenate(lists)
    hyp = np.repeat(np.arange(len(lists)), [len(t) for t in lists])
    p = np.bincount(idx, weights=w[hyp], minlength=int(idx.max()) + 1)
    return h, np.minimum(p[lists[h]], 1.0)  # a sum of normalised weights may round a hair above 1


def map_label_marginals(state) -> tuple[np.ndarray, np.ndarray]:
    """``(labels, P)`` of the factored posterior as held (:meth:`~.engine.FactoredFilter.state`): the MAP's labels in
    the order of :meth:`~.engine.FactoredFilter.estimates` (each group's MAP tracks, then the lane's singletons) and
    each one's :func:`map_track_marginals` (1 for a singleton). Lazy groups are read as held: their weights do not
    change out of view."""
    labels, probs = [], []
    for g in state.groups.states:
        h, p = map_track_marginals(g.log_w, g.tracks)
        labels.append(np.asarray(g.store.labels, dtype=np.int64)[np.asarray(g.tracks[h], dtype=np.int64)])
        probs.append(p)
    labels.append(np.asarray(state.lane.store.labels, dtype=np.int64))
    probs.append(np.ones(len(state.lane.store.labels)))
    return np.concatenate(labels), np.concatenate(probs)
