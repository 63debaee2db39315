"""State-dependent detection probability: the hook a sensor's ``detection.p_D_of`` plugs into.

A sensor's ``detection`` has one ``p_D`` and an ``in_view`` test; the engine's track columns then hold
``p_D`` in view and 0 out of it (:meth:`~.filter.HypothesisFilter.track_scores`). A detection that also
has ``p_D_of(means (n, d)) -> (n,)`` — e.g. the catalogue radar's marginal SNR p_D of a predicted
range (:class:`hypotrack.scenarios.catalogue.snr.SnrTrackerDetection`) — gives each track in view its
own ``p_D`` from its predicted mean; out of view it stays 0. Without ``p_D_of`` nothing changes (the
same array is returned), so constant-``p_D`` runs are unchanged bit for bit. A detection with
``p_D_of_moments(means, covs) -> (n,)`` — the field of view's edge integrated over each track's predicted
density (:class:`hypotrack.scenarios.catalogue.fov_edge.SoftEdgeDetection`) — gives each track in view that
``p_D`` instead, when the covariances are passed.
"""

from __future__ import annotations

import numpy as np

__all__ = ["state_p_detect"]


def state_p_detect(detection, means, p_detect, covs=None) -> np.ndarray:
    """``p_detect`` (n,) with ``detection.p_D_of_moments(means, covs)`` (when it has one and ``covs`` is given),
    else ``detection.p_D_of(means)``, in place of the constant where it is > 0 (in view); ``p_detect`` itself
    when ``detection`` has neither or there are no tracks.

    Each value must lie in [0, 1) (``log(1 − p_D)`` of a missed track is in every hypothesis weight)."""
    p_mom = getattr(detection, "p_D_of_moments", None) if covs is not None else None
    p_of = getattr(detection, "p_D_of", None)
    if (p_mom is None and p_of is None) or len(p_detect) == 0:
        return p_detect
    name = "p_D_of_moments" if p_mom is not None else "p_D_of"
    p = np.asarray(p_mom(means, covs) if p_mom is not None else p_of(means), dtype=float)
    if p.shape != np.shape(p_detect) or not np.all((p >= 0) & (p < 1)):
        raise ValueError(f"detection.{name} must return one p_D in [0, 1) per track, shape {np.shape(p_detect)}")
    return np.where(p_detect > 0, p, 0.0)
