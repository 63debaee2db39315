"""The catalogue model's optional physics (``ssa_catalogue.model`` / ``ssa_breakup.model``): a death model
for tracks never confirmed and the orbit plausibility test.

* ``unconfirmed_decay: {p_tentative, velocity_std_km_s[, p_confirmed]}`` (or ``null``, the default) — the
  δ-GLMB presets' per-track survival :class:`hypotrack.hypotheses.UnconfirmedDecay`: a track whose largest
  velocity standard deviation exceeds ``velocity_std_km_s`` (born from one return, never re-detected)
  survives each scan with ``p_tentative``, so its existence after ``k`` scans out of view is
  ``r p_tentative^k`` and a false entry leaves the catalogue after ``ceil(log(w/r) / log p_tentative)``
  scans (``w`` the engine's ``min_weight``); a confirmed one with ``p_confirmed`` (default 1: a catalogued
  object out of view for an orbit stays).
* ``plausibility: true`` — ``validity = plausible_orbits`` (bound, perigee >= 100 km;
  :mod:`hypotrack.models.plausibility`) for every tracker: the engine gives a hypothesis holding an
  unphysical track weight 0, GNN/JPDA delete such a track. Off unless set: a one-point birth has a
  zero-mean velocity, i.e. falls straight down, and fails the test. With ``birth: admissible`` every tracker's
  births are the admissible region's mixture (δ-GLMB's and R-FISST's birth terms, HOMHT's seeded births,
  GNN/JPDA's tentative tracks), whose means are bound orbits above the floor, and the catalogue and breakup
  configurations turn it on.
* ``radar.snr: {wavelength_m, ref_diameter_m, ref_range_km, ref_p_D, p_fa}`` (optional; absent: the constant
  ``radar.p_D``) — SNR detection (:mod:`hypotrack.scenarios.catalogue.snr`): the returns detect each object
  with the Swerling I p_D of its stated size (:class:`~hypotrack.scenarios.catalogue.snr.SizeModel`, one draw,
  seed :data:`SIZE_SEED`: sizes are a property of the objects, the same in every run) at its range, and the
  trackers' ``detection.p_D_of`` is the marginal over the size model with the config's ``debris_share``.
"""

from __future__ import annotations

from ...hypotheses import UnconfirmedDecay
from ...models.plausibility import plausible_orbits
from ...scenarios.catalogue.snr import SizeModel, SnrModel, attach_snr_detection

__all__ = ["model_survival", "model_validity", "radar_snr", "object_sizes", "attach_tracker_snr", "SIZE_SEED"]

SIZE_SEED = 0
"""Seed of the objects' stated sizes (:meth:`SizeModel.sizes`)."""


def model_survival(model: dict):
    """The :class:`UnconfirmedDecay` of ``model["unconfirmed_decay"]``, or ``None`` (absent or null)."""
    d = model.get("unconfirmed_decay")
    if d is None:
        return None
    if not isinstance(d, dict) or not {"p_tentative", "velocity_std_km_s"} <= set(d):
        raise ValueError("model.unconfirmed_decay must be null or a mapping with p_tentative in (0, 1) and "
                         f"velocity_std_km_s > 0 (optional p_confirmed in (0, 1]), got {d!r}")
    return UnconfirmedDecay(p_tentative=d["p_tentative"], velocity_std=d["velocity_std_km_s"],
                            p_confirmed=d.get("p_confirmed", 1.0))


def model_validity(model: dict):
    """``plausible_orbits`` when ``model["plausibility"]`` is true, else ``None``."""
    v = model.get("plausibility", False)
    if not isinstance(v, bool):
        raise ValueError(f"model.plausibility must be true or false, got {v!r}")
    return plausible_orbits if v else None


def radar_snr(radar: dict):
    """The :class:`SnrModel` of ``radar["snr"]``, or ``None`` (absent or null: constant ``p_D``)."""
    block = radar.get("snr")
    return None if block is None else SnrModel(**block)


def object_sizes(cfg: dict, objects):
    """The stated sizes (m) of ``objects`` when ``radar.snr`` is set (the truth's SNR p_D needs them), else ``None``."""
    return None if radar_snr(cfg["radar"]) is None else SizeModel().sizes(objects, seed=SIZE_SEED)


def attach_tracker_snr(cfg: dict, tsensor):
    """Give the tracker sensor the marginal SNR p_D (:func:`attach_snr_detection`, size model with the config's
    ``debris_share``; a section without one, the breakup cloud's, is all fragments: 1) when ``radar.snr`` is set;
    returns ``tsensor``."""
    model = radar_snr(cfg["radar"])
    if model is None:
        return tsensor
    return attach_snr_detection(tsensor, model, SizeModel(debris_share=float(cfg.get("debris_share", 1.0))))
