"""The hypothesis engine's parts by hand: scan context, track store, hypotheses and child sets,
association problems, posterior summaries, presets and synthetic problems."""

import numpy as np
import pytest

from hypotrack.hypotheses import ScanContext


def _ctx(m=3, n=2, B=1, rate=2.0, volume=400.0):
    return ScanContext(Z=np.zeros((m, 2)), loglik=np.zeros((m, n)), allowed=np.ones((m, n), bool),
                       p_detect=np.full(n, 0.9), birth_loglik=np.zeros((m, B)), p_detect_birth=0.9,
                       clutter_rate=rate, clutter_volume=volume)


def test_scan_context_counts_and_clutter_terms():
    ctx = _ctx(m=3, n=2, B=4, rate=2.0, volume=400.0)
    assert ctx.n_returns == 3
    assert ctx.n_birth_regions == 4
    assert ctx.clutter_intensity == 2.0 / 400.0
    assert ctx.log_clutter_density == pytest.approx(-np.log(400.0), abs=1e-15)
