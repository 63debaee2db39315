"""The catalogue scenario: the real orbital population (TLEs, SGP4) seen by ground radars.

Modules, in data-flow order:

* :mod:`.tle` — read three-line element files into a catalogue table; the bundled, checksum-verified
  CelesTrak catalogues (:func:`load_catalogue`: active satellites 2022-11-03, three debris clouds
  2021-10-02, 10,855 objects); deterministic selections (by group, seeded sample, altitude band);
* :mod:`.propagation` — SGP4 over a time grid for the whole catalogue at once (TEME, km, km/s);
* :mod:`.frames` — UTC → Julian date, GMST, TEME → Earth-fixed, geodetic sites, RAE;
* :mod:`.sensors` — ground radars (site, field of view, revisit, noise, p_D, Poisson clutter);
* :mod:`.scenario` — :func:`simulate_catalogue`: truth and scans tables in the project's schema;
* :mod:`.benchmark` — propagation cost and the two-body model's one-scan prediction error vs SGP4;
* :mod:`.tracking` — the trackers' linear view of an ENU radar (TEME positions) and one-point births;
* :mod:`.radar_model` — the documented radar model for trackers: range, azimuth, elevation, range-rate
  of a TEME state, its analytic Jacobian, noise and the azimuth-wrapped innovation;
* :mod:`.admissible` — admissible-region birth: the Gaussian mixture of a new object's state given one
  return (bound orbit, perigee >= 100 km; the test is :func:`hypotrack.models.plausibility.plausible_orbits`);
* :mod:`.sbm` — the NASA standard breakup model (fragment sizes, area-to-mass ratios, ejection speeds);
* :mod:`.breakup` — a fresh breakup cloud of a bundled parent orbit (two-body + J2 truth) seen by a radar.
* :mod:`.snr` — detection from the signal-to-noise ratio: object size → RCS → SNR (radar equation) →
  Swerling I p_D; stated sizes of the bundled objects; the trackers' marginal p_D of a predicted range;
* :mod:`.fence` — a fence sensor (S-band, Kwajalein) with a thin elevation band: a few returns per crossing.

Example (``import pandas as pd``)::

    from hypotrack.scenarios.catalogue import load_catalogue, sample_objects, select_groups, simulate_catalogue
    cat = load_catalogue()
    objects = pd.concat([sample_objects(select_groups(cat, "active"), 1000, seed=1),
                         select_groups(cat, "fengyun-1c-debris")], ignore_index=True)
    sc = simulate_catalogue(objects, n_scans=360, seed=2)   # 1 h of the default radar
"""

from .admissible import AdmissibleRegionBirth, attributable_to_state
from .frames import gmst, julian_date, teme_to_ef
from .propagation import Propagation, propagate, reference_epoch
from .radar_model import RadarTrackerSensor, rae_rate, rae_rate_jacobian
from .scenario import CatalogueScenario, simulate_catalogue
from .sensors import DEFAULT_RADAR, DEFAULT_SITE, GroundRadar, GroundSite, RadarFieldOfView
from .tle import (
    BUNDLED,
    DEBRIS_GROUPS,
    GROUPS,
    load_catalogue,
    parse_tle,
    read_tle,
    sample_objects,
    satrec_array,
    select_altitude,
    select_groups,
)

__all__ = [
    "BUNDLED",
    "GROUPS",
    "DEBRIS_GROUPS",
    "load_catalogue",
    "parse_tle",
    "read_tle",
    "select_groups",
    "sample_objects",
    "select_altitude",
    "satrec_array",
    "Propagation",
    "propagate",
    "reference_epoch",
    "gmst",
    "julian_date",
    "teme_to_ef",
    "GroundSite",
    "RadarFieldOfView",
    "GroundRadar",
    "DEFAULT_SITE",
    "DEFAULT_RADAR",
    "CatalogueScenario",
    "simulate_catalogue",
    "RadarTrackerSensor",
    "rae_rate",
    "rae_rate_jacobian",
    "AdmissibleRegionBirth",
    "attributable_to_state",
]
