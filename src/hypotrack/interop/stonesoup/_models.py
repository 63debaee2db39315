"""Stone Soup models → hypotrack's: the tracker's models once, each detection's model once per model object."""

from __future__ import annotations

import numpy as np

from ...models import ConstantVelocity
from ...models.sensors import Box, LinearPositionSensor
from ._common import require_stonesoup

__all__ = ["translate_models", "stonesoup_order", "DetectionFrame"]


def stonesoup_order(n_spatial: int) -> np.ndarray:
    """``perm`` with hypotrack state component ``i`` = Stone Soup component ``perm[i]``.

    Stone Soup stacks one ``ConstantVelocity`` per axis (``[x, vx, y, vy, ..]``), hypotrack puts
    positions first (``[x, y, .., vx, vy, ..]``).
    """
    k = int(n_spatial)
    return np.concatenate([2 * np.arange(k), 2 * np.arange(k) + 1])


def translate_models(transition_model, measurement_model):
    """Translate Stone Soup models into hypotrack's, once.

    Parameters
    ----------
    transition_model : stonesoup CombinedLinearGaussianTransitionModel or ConstantVelocity
        One ``ConstantVelocity`` per spatial axis (1 to 3), all with the same ``noise_diff_coeff``.
    measurement_model : stonesoup LinearGaussian
        Position measurement: ``mapping`` selects position components, ``noise_covar`` is ``R``.

    Returns
    -------
    motion : hypotrack.models.ConstantVelocity
    measurement : hypotrack.models.sensors.LinearPositionSensor
    perm : (d,) int array
        hypotrack state component ``i`` is Stone Soup component ``perm[i]``.
    """
    require_stonesoup()
    from stonesoup.models.base import GaussianModel, LinearModel
    from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel
    from stonesoup.models.transition.linear import ConstantVelocity as SSConstantVelocity

    parts = (
        list(transition_model.model_list)
        if isinstance(transition_model, CombinedLinearGaussianTransitionModel) else [transition_model]
    )
    if not 1 <= len(parts) <= 3 or not all(type(p) is SSConstantVelocity for p in parts):
        raise ValueError(
            "transition_model must be a ConstantVelocity or a CombinedLinearGaussianTransitionModel of 1 to 3 "
            f"ConstantVelocity models, got {[type(p).__name__ for p in parts]}"
        )
    qs = {float(p.noise_diff_coeff) for p in parts}
    if len(qs) != 1:
        raise ValueError(f"transition_model: every axis must share one noise_diff_coeff, got {sorted(qs)}")
    k = len(parts)
    perm = stonesoup_order(k)
    inverse = np.argsort(perm)
    supported = (f"supported: a linear-Gaussian position measurement (e.g. LinearGaussian({2 * k}, mapping, "
                 f"noise_covar)) whose mapping selects position components among {tuple(range(0, 2 * k, 2))} of "
                 f"Stone Soup's [x, vx, y, vy, ...] state; convert non-linear returns (bearing-range, ...) to "
                 "Cartesian positions first")
    if not (isinstance(measurement_model, LinearModel) and isinstance(measurement_model, GaussianModel)):
        raise ValueError(f"measurement_model {type(measurement_model).__name__} is not a linear-Gaussian model (the "
                         f"trackers are linear Kalman filters and would read its components as positions); {supported}")
    if int(measurement_model.ndim_state) != 2 * k:
        raise ValueError(
            f"measurement_model.ndim_state must be {2 * k} (the transition model's), got {measurement_model.ndim_state}"
        )
    mapping = tuple(int(i) for i in getattr(measurement_model, "mapping", ()))
    selection = np.zeros((len(mapping), 2 * k))
    selection[np.arange(len(mapping)), list(mapping)] = 1.0
    if (not mapping or any(i % 2 for i in mapping) or len(set(mapping)) != len(mapping)
            or not np.array_equal(np.asarray(measurement_model.matrix(), dtype=float), selection)):
        raise ValueError(f"measurement_model {type(measurement_model).__name__} with mapping {mapping} does not "
                         f"measure distinct position components alone; {supported}")
    position_indices = tuple(int(inverse[i]) for i in measurement_model.mapping)
    R = np.asarray(measurement_model.covar(), dtype=float)
    measurement = LinearPositionSensor(R, ndim_state=2 * k, position_indices=position_indices)
    return ConstantVelocity(q=qs.pop(), n_spatial=k), measurement, perm


def _region(clutter_region, dim):
    region = np.asarray(clutter_region, dtype=float)
    if region.shape != (dim, 2):
        raise ValueError(f"clutter_region must have shape ({dim}, 2) ([[low, high], ...] per measured axis), "
                         f"got {region.shape}")
    return Box(region[:, 0], region[:, 1])


class _Frame:
    """How one detection measurement model maps onto the tracker's: ``z' = A⁻¹ z``, ``R' = A⁻¹ R_d A⁻ᵀ``.

    ``source`` (a permutation, exact) or ``A_inv`` (a general invertible ``A``); ``variant`` is
    ``None`` when ``R'`` is the tracker's ``R`` (the detection is then just re-ordered), else the
    index of ``R'`` among the distinct covariances seen so far.
    """

    __slots__ = ("model", "source", "A_inv", "variant")

    def __init__(self, model, source, A_inv, variant):
        self.model, self.source, self.A_inv, self.variant = model, source, A_inv, variant


class DetectionFrame:
    """Detections of a scan → the tracker's returns ``Z`` (m, p) in the tracker's measurement frame.

    A Stone Soup detection may carry its own ``measurement_model``. The hypotrack trackers are
    linear Kalman filters with one ``H`` and ``R`` per scan, so a detection's model is accepted
    when it is linear-Gaussian on the tracker's state and measures the same state components as
    the tracker's model, in any order or linear combination: ``H_d = A H`` with ``A`` invertible
    (``H`` the tracker's). Then ``z' = A⁻¹ z`` is a measurement of ``H x`` with noise
    ``R' = A⁻¹ R_d A⁻ᵀ`` — the same information, expressed in the tracker's frame. A permuted
    ``mapping`` (e.g. ``(2, 0)`` for a tracker measuring ``(0, 2)``) is a permutation ``A``,
    applied exactly by indexing. When ``R'`` differs from the tracker's ``R`` the scan is run
    with ``R'`` (:attr:`variants`); a scan whose detections need two different ``R'`` is refused.

    Everything else raises ``ValueError`` naming ``measurement_model`` (non-linear models such as
    ``CartesianToBearingRange``, another ``ndim_state`` or ``ndim_meas``, other state components)
    or ``state_vector`` (a detection whose vector has not ``ndim_meas`` rows): a state vector is
    never reshaped into returns of another size.

    Each model object is checked and translated once (cached by identity).
    """

    def __init__(self, measurement_model, perm, H, R):
        self.default = measurement_model
        self.perm = np.asarray(perm)
        self.H = np.asarray(H, dtype=float)  # tracker's H in hypotrack's state order (a selection)
        self.R = np.asarray(R, dtype=float)
        self.p, self.d = self.H.shape
        self.variants: list[np.ndarray] = []  # distinct R' ≠ R, in order of first appearance
        self._frames: dict[int, _Frame] = {}
        self._allowed = (
            f"a detection's measurement_model must be linear-Gaussian (e.g. LinearGaussian) with ndim_state="
            f"{self.d} and ndim_meas={self.p}, measuring the state components the tracker's measurement_model "
            f"measures (mapping {tuple(int(i) for i in measurement_model.mapping)}, in any order) with any "
            "noise_covar, or None (the tracker's measurement_model)"
        )

    # ------------------------------------------------------------------ models
    def _frame(self, model) -> _Frame:
        frame = self._frames.get(id(model))
        if frame is not None and frame.model is model:
            return frame
        if len(self._frames) > 1024:  # a new model object per detection: do not grow without bound
            self._frames.clear()
        frame = self._frames[id(model)] = self._translate(model)
        return frame

    def _refuse(self, model, why):
        raise ValueError(f"measurement_model {type(model).__name__} of a detection is not usable: {why}; "
                         f"{self._allowed}")

    def _translate(self, model) -> _Frame:
        from stonesoup.models.base import GaussianModel, LinearModel

        if not (isinstance(model, LinearModel) and isinstance(model, GaussianModel)):
            self._refuse(model, "it is not a linear-Gaussian model (the trackers are linear Kalman filters; convert "
                                "non-linear detections, e.g. bearing-range, to Cartesian positions first)")
        if int(model.ndim_state) != self.d:
            self._refuse(model, f"ndim_state is {model.ndim_state}, the tracker's state has {self.d} components")
        if int(model.ndim_meas) != self.p:
            self._refuse(model, f"ndim_meas is {model.ndim_meas}, the tracker's measurement_model has {self.p}")
        H_d = np.asarray(model.matrix(), dtype=float)[:, self.perm]  # hypotrack state order
        R_d = np.asarray(model.covar(), dtype=float)
        A = H_d @ self.H.T  # H is a selection: H Hᵀ = I, so H_d = A H iff H_d = (H_d Hᵀ) H
        if not np.allclose(A @ self.H, H_d, rtol=0.0, atol=1e-12 * max(1.0, np.abs(H_d).max())) or (
                np.linalg.cond(A) > 1e12):
            measured = sorted({int(self.perm[j]) for j in np.flatnonzero(np.abs(H_d).sum(axis=0))})
            self._refuse(model, f"it measures state components {measured}, not (an invertible combination of) "
                                f"the tracker's {sorted(int(self.perm[j]) for j in self.H.argmax(axis=1))}")
        is_perm = np.all((A == 0.0) | (A == 1.0)) and np.all(A.sum(axis=0) == 1) and np.all(A.sum(axis=1) == 1)
        if is_perm:
            source = A.argmax(axis=0)  # z'[k] = z[source[k]], exactly
            R_t, A_inv = R_d[np.ix_(source, source)], None
        else:
            source, A_inv = None, np.linalg.inv(A)
            R_t = A_inv @ R_d @ A_inv.T
            R_t = 0.5 * (R_t + R_t.T)
        return _Frame(model, source, A_inv, self._variant(R_t))

    def _variant(self, R_t):
        if np.allclose(R_t, self.R, rtol=1e-12, atol=0.0):
            return None
        for v, R_v in enumerate(self.variants):
            if np.allclose(R_t, R_v, rtol=1e-12, atol=0.0):
                return v
        try:
            np.linalg.cholesky(R_t)
        except np.linalg.LinAlgError:
            raise ValueError(f"measurement_model of a detection has a noise covariance that is not positive "
                             f"definite: {R_t.tolist()}; {self._allowed}") from None
        self.variants.append(R_t)
        return len(self.variants) - 1

    # ------------------------------------------------------------------ scans
    def returns(self, detections, time):
        """``(Z, detections, variant)``: returns sorted lexicographically (a seeded run is reproducible
        whatever the set's order), the detections in the same order, and the index in
        :attr:`variants` of the scan's noise covariance (``None``: the tracker's ``R``)."""
        from stonesoup.types.detection import Detection

        if isinstance(detections, (np.ndarray, str, bytes)) or not hasattr(detections, "__iter__"):
            raise TypeError(f"detections must be a set (or list) of Stone Soup Detections, got "
                            f"{type(detections).__name__}")
        dets = list(detections)
        m, p, default = len(dets), self.p, self.default
        if m == 0:
            return np.zeros((0, p)), dets, None
        for det in dets:
            if not isinstance(det, Detection):
                raise TypeError(f"detections must be Stone Soup Detections (state_vector, timestamp, "
                                f"measurement_model), got a {type(det).__name__}: {det!r}"[:300])
            if det.timestamp is not None and det.timestamp != time:
                raise ValueError(f"detection at {np.ravel(det.state_vector).tolist()} ({type(det).__name__}) has "
                                 f"timestamp {det.timestamp}, but its scan's time is {time}: "
                                 "every detection of a scan must carry the scan's time (or none); yield "
                                 "detections of another time as their own scan")
        frames = [None if (mm := det.measurement_model) is None or mm is default else self._frame(mm)
                  for det in dets]
        # Plain ndarray views: numpy's conversion of Stone Soup's StateVector subclass is 3x slower.
        vectors = [det.state_vector.view(np.ndarray) for det in dets]
        shapes = {v.shape for v in vectors}
        if shapes != {(p, 1)}:
            bad = sorted(str(s) for s in shapes - {(p, 1)})
            raise ValueError(f"state_vector of a detection at {time} has shape {', '.join(bad)}; the "
                             f"measurement_model measures {p} components, so every detection's state_vector "
                             f"must have shape ({p}, 1) (a vector is never reshaped into returns of another size)")
        Z = np.array(vectors, dtype=float).reshape(m, p)
        variants = {None if f is None else f.variant for f in frames}
        if len(variants) > 1:
            raise ValueError(
                f"measurement_model: detections at {time} carry {len(variants)} different noise covariances "
                "(in the tracker's measurement order); the trackers take one H and R per scan. Yield each "
                "sensor's detections as its own scan (the same timestamp is allowed: it is processed as an "
                "additional scan with no prediction)")
        for i, f in enumerate(frames):
            if f is not None:
                Z[i] = Z[i, f.source] if f.A_inv is None else f.A_inv @ Z[i]
        order = np.lexsort(Z.T[::-1])
        return Z[order], [dets[i] for i in order], variants.pop()
