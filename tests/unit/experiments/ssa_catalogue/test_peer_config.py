"""The Stone Soup peer comparison runs on the ENU stand-in radar whatever radar the catalogue tracks with."""

import copy
from pathlib import Path

import numpy as np
import yaml

from hypotrack.experiments.ssa_catalogue.run import peer_config, peer_scenario

ROOT = Path(__file__).resolve().parents[4]


def test_peer_scenario_of_a_radar_frame_section_is_the_linear_stand_in():
    with open(ROOT / "workflows" / "config" / "default.yaml") as fh:
        cfg = copy.deepcopy(yaml.safe_load(fh)["ssa_catalogue"])
    cfg["n_scans"] = 3
    cfg["radar"].update(measurement="rae_rate", sigma_range_km=0.03, sigma_angle_deg=0.05, sigma_range_rate_km_s=0.01)
    plain = peer_config(cfg)
    assert "measurement" not in plain["radar"] and "snr" not in plain["radar"] and "sigma_range_km" not in plain["radar"]
    assert cfg["radar"]["measurement"] == "rae_rate"  # the section itself is untouched
    ps = peer_scenario(cfg, 30, 1)
    sigma = cfg["radar"]["sigma_km"]
    np.testing.assert_array_equal(ps.model.H, np.hstack([np.eye(3), np.zeros((3, 3))]))
    np.testing.assert_allclose(ps.model.R, sigma**2 * np.eye(3), rtol=1e-15)
    assert ps.model.p_D == cfg["radar"]["p_D"] and all(z.shape[1] == 3 for z in ps.returns)
