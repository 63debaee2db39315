"""The fast path on the real catalogue's scans: the δ-GLMB and HOMHT k-best trackers of the default
configuration (N = 100) hold, scan for scan, bit for bit the posterior of the general path."""

import yaml

from hypotrack.experiments.ssa_catalogue.fast_path import fast_path_timing
from hypotrack.experiments.ssa_catalogue.run import peer_config


def test_catalogue_trackers_hold_the_general_posterior_with_the_fast_path():
    with open("workflows/config/default.yaml") as fh:
        cfg = dict(yaml.safe_load(fh)["ssa_catalogue"], n_scans=30)
    cfg = peer_config(cfg)  # the ENU stand-in: a fixed H, where the fast path is the general one bit for bit
    cfg["model"] = {k: v for k, v in cfg["model"].items() if k not in ("birth", "plausibility")}
    df = fast_path_timing(cfg, 100, 1, ("glmb", "homht_kbest"), n_scans=30, warm_scans=0, warm_run=False)
    assert len(df) == 4 and df["identical"].all() and (df["stopped"] == "").all()
    assert (df["n_scans"] == 30).all()
    on = df[df["fast_path"]]
    assert (on["fast_share"] > 0.2).all()  # the fast path took lone tracks: the check is not vacuous
    assert (df[~df["fast_path"]]["fast_share"] == 0).all()
