"""The NASA standard breakup model against the published laws (Johnson, Krisko, Liou & Anz-Meador 2001,
"NASA's new breakup model of EVOLVE 4.0", Adv. Space Res. 28(9)), in the paper's own piecewise form, and the
samplers against their documented draws (a generator replayed from the same seed, or a fixed one)."""

import numpy as np
import pytest

from hypotrack.scenarios.catalogue.sbm import (DELTA_V_SIGMA_LOG10, am_parameters, delta_v_mean_log10,
                                                sample_area_to_mass, sample_breakup, sample_delta_v, sample_sizes,
                                                sbm_count)


def _paper(lam, parent):
    """The A/M parameters as the paper writes them (slope-intercept pieces, its rounded slopes): Eq. 6 (small
    fragments, both parents), Eq. 7 (spacecraft above 11 cm), Eq. 5 (upper stages above 11 cm)."""
    def piece(x, lo, hi, y_lo, y_hi, mid):
        return y_lo if x <= lo else (y_hi if x >= hi else mid(x))
    mu_s = piece(lam, -1.75, -1.25, -0.3, -1.0, lambda x: -0.3 - 1.4 * (x + 1.75))
    sd_s = 0.2 if lam <= -3.5 else 0.2 + 0.1333 * (lam + 3.5)
    if parent == "spacecraft":
        alpha = piece(lam, -1.95, 0.55, 0.0, 1.0, lambda x: 0.3 + 0.4 * (x + 1.2))
        mu1 = piece(lam, -1.1, 0.0, -0.6, -0.95, lambda x: -0.6 - 0.318 * (x + 1.1))
        sd1 = piece(lam, -1.3, -0.3, 0.1, 0.3, lambda x: 0.1 + 0.2 * (x + 1.3))
        mu2 = piece(lam, -0.7, -0.1, -1.2, -2.0, lambda x: -1.2 - 1.333 * (x + 0.7))
        sd2 = piece(lam, -0.5, -0.3, 0.5, 0.3, lambda x: 0.5 - (x + 0.5))
    else:
        alpha = piece(lam, -1.4, 0.0, 1.0, 0.5, lambda x: 1.0 - 0.3571 * (x + 1.4))
        mu1 = piece(lam, -0.5, 0.0, -0.45, -0.9, lambda x: -0.45 - 0.9 * (x + 0.5))
        sd1 = 0.55
        mu2 = -0.9
        sd2 = piece(lam, -1.0, 0.1, 0.28, 0.1, lambda x: 0.28 - 0.1636 * (x + 1.0))
    return mu_s, sd_s, alpha, mu1, sd1, mu2, sd2


# log10 L_c inside every piece of every law and on both plateaus (-4 below the small law's sigma knee at -3.5)
LAMBDAS = [-4.0, -3.0, -2.2, -1.6, -1.4, -1.2, -1.0, -0.8, -0.6, -0.45, -0.4, -0.35, -0.2, -0.05, 0.05, 0.3, 1.0]
# the paper's slopes are rounded (0.318 = 0.35 / 1.1, 1.333 = 0.8 / 0.6, 0.3571 = 0.5 / 1.4, 0.1636 = 0.18 / 1.1):
# at most 2e-4 apart from the ramps between the end points, which the module uses
PAPER_ROUNDING = 3e-4


@pytest.mark.parametrize("parent", ["spacecraft", "rocket_body"])
def test_area_to_mass_parameters_match_the_paper(parent):
    got = np.array(am_parameters(10.0 ** np.array(LAMBDAS), parent))
    want = np.array([_paper(lam, parent) for lam in LAMBDAS]).T
    assert got.shape == want.shape == (7, len(LAMBDAS))  # every parameter an array like lc_m
    assert got == pytest.approx(want, abs=PAPER_ROUNDING)


def test_area_to_mass_parameters_by_hand_at_knees():
    # below lambda = -3.5 the small law's sigma is 0.2 (1e-4 m: lambda = -4); at the knee the pieces meet
    assert float(am_parameters(1e-4)[1]) == pytest.approx(0.2, abs=1e-12)
    assert float(am_parameters(10**-3.5)[1]) == pytest.approx(0.2, abs=1e-12)
    # upper stage at lambda = -1: alpha = 1 - 0.3571 * 0.4 = 0.85716 (ramp: 1 - 0.4 / 2.8 = 0.857143),
    # mu1 = -0.45 (plateau), sigma2 = 0.28 (knee)
    _, _, a, m1, s1, m2, s2 = am_parameters(0.1, "rocket_body")
    assert (float(a), float(m1), float(s2)) == pytest.approx((1 - 0.4 / 2.8, -0.45, 0.28), abs=1e-12)
    # the constant parameters come back one per size, like the varying ones
    _, _, _, _, s1, m2, _ = am_parameters([0.5, 1.0, 2.0], "rocket_body")
    assert s1.tolist() == [0.55] * 3 and m2.tolist() == [-0.9] * 3


def test_single_precision_sizes_are_computed_in_double():
    # lc given as float32: the laws are evaluated at the double value of that size (log10 in float32 is off by
    # ~1e-8, and the constants 0.55 and -0.9 would be stored as 0.550000012 and -0.899999976)
    for parent in ("spacecraft", "rocket_body"):
        lc32 = np.array([0.05, 0.3, 2.0], dtype=np.float32)
        got = am_parameters(lc32, parent)
        want = am_parameters(lc32.astype(np.float64), parent)
        for g, w in zip(got, want):
            assert np.asarray(g).dtype == np.float64
            assert np.array_equal(g, w)
    chi32 = np.array([-2.5, -0.3], dtype=np.float32)
    for kind in ("explosion", "collision"):
        assert np.array_equal(delta_v_mean_log10(chi32, kind), delta_v_mean_log10(chi32.astype(np.float64), kind))


def test_delta_v_mean_by_hand():
    # chi = -2: explosion 0.2 * -2 + 1.85 = 1.45; collision 0.9 * -2 + 2.9 = 1.1 (chi = -1 cannot tell a
    # product from a quotient)
    assert delta_v_mean_log10([-2.0, 0.5], "explosion") == pytest.approx([1.45, 1.95], abs=1e-12)
    assert delta_v_mean_log10([-2.0, 0.5], "collision") == pytest.approx([1.1, 3.35], abs=1e-12)


def test_delta_v_samples_replay_the_draws():
    # one standard normal z per fragment: dv = 10^(mean + 0.4 z)
    chi = np.array([-2.0, -1.0, 0.0, 0.5])
    z = np.random.default_rng(11).standard_normal(4)
    for kind in ("explosion", "collision"):
        want = 10.0 ** (delta_v_mean_log10(chi, kind) + DELTA_V_SIGMA_LOG10 * z)
        assert sample_delta_v(chi, kind, np.random.default_rng(11)) == pytest.approx(want, rel=1e-12)


def _replayed_chi(lc, seed, parent):
    """χ from the documented draws (bridge uniforms, mixture uniforms, normals) and the paper's parameters."""
    rng = np.random.default_rng(seed)
    n = len(lc)
    u_bridge, u_mix, z = rng.random(n), rng.random(n), rng.standard_normal(n)
    lo, hi = np.log10(0.08), np.log10(0.11)
    out = []
    for L, ub, um, zi in zip(lc, u_bridge, u_mix, z):
        lam = np.log10(L)
        mu_s, sd_s, alpha, mu1, sd1, mu2, sd2 = _paper(lam, parent)
        p_large = min(1.0, max(0.0, (lam - lo) / (hi - lo)))
        if ub < p_large:
            out.append(mu1 + sd1 * zi if um < alpha else mu2 + sd2 * zi)
        else:
            out.append(mu_s + sd_s * zi)
    return np.array(out)


@pytest.mark.parametrize("parent", ["spacecraft", "rocket_body"])
def test_area_to_mass_samples_replay_the_draws(parent):
    # sizes in every regime: small (< 8 cm), the 8-11 cm bridge, large; repeated so both bridge outcomes and
    # both mixture components occur
    lc = np.tile([0.001, 0.05, 0.085, 0.09, 0.095, 0.1, 0.105, 0.2, 0.5, 1.0, 5.0], 20)
    got = sample_area_to_mass(lc, np.random.default_rng(21), parent)
    # |z| < 4 times the paper's rounding of the parameters
    assert got == pytest.approx(_replayed_chi(lc, 21, parent), abs=4 * PAPER_ROUNDING + 1e-12)


class _Fixed:
    """A generator stand-in handing out the given uniforms and normals in order."""

    def __init__(self, uniforms, normals):
        self.u, self.z = list(uniforms), list(normals)

    def random(self, n):
        out, self.u = np.array(self.u[:n], dtype=float), self.u[n:]
        return out

    def standard_normal(self, n):
        out, self.z = np.array(self.z[:n], dtype=float), self.z[n:]
        return out


def test_area_to_mass_draw_conventions_by_hand():
    # sizes 1 cm (bridge probability 0), 1 m spacecraft; bridge uniforms 0 and 0; mixture uniforms 0 and 0.9;
    # normals 1 and 1. 1 cm: a uniform of 0 is not below probability 0, so the small law: mu_s = -0.3,
    # sigma_s = 0.2 + 0.1333 * 1.5 = 0.39995 -> 0.09995. 1 m: large; 0.9 >= alpha = 0.78, so the second
    # component: -2.0 + 0.3 = -1.7
    chi = sample_area_to_mass([0.01, 1.0], _Fixed([0.0, 0.0, 0.0, 0.9], [1.0, 1.0]))
    assert chi == pytest.approx([0.09995, -1.7], abs=1e-12)
    # upper stage at 1 m, alpha = 0.5: a mixture uniform of 0.5 is not below alpha -> second component
    # mu2 = -0.9, sigma2 = 0.1164 (ramp 0.28 - 0.18 / 1.1 = 0.116364), normal -1 -> -1.016364; 0.49 -> first,
    # mu1 = -0.9, sigma1 = 0.55 -> -1.45
    chi = sample_area_to_mass([1.0, 1.0], _Fixed([0.0, 0.0, 0.5, 0.49], [-1.0, -1.0]), "rocket_body")
    assert chi == pytest.approx([-0.9 - (0.28 - 0.18 / 1.1), -1.45], abs=1e-12)


def test_bridge_probability_of_single_precision_size():
    # a float32 size of 0.0975 m: the bridge probability is that of its double value p (log10 in float32
    # would give p + 9e-8). A bridge uniform equal to p is not below it: the small law,
    # mu_s = -1.0, sigma_s = 0.2 + 0.1333 * (lambda + 3.5), normal 0 -> -1.0 (the large law would give mu1 or
    # mu2 of the spacecraft: -0.6 or -1.2)
    lc32 = np.array([0.0975], dtype=np.float32)
    lam = np.log10(float(lc32[0]))
    p = float(np.interp(lam, [np.log10(0.08), np.log10(0.11)], [0.0, 1.0]))
    chi = sample_area_to_mass(lc32, _Fixed([p, 0.0], [0.0]))
    assert chi == pytest.approx([-1.0], abs=1e-12)


def test_breakup_composition_replays_the_draws():
    # sizes, A/M, speeds, directions from one generator in that order; the scaling factor sets the count
    # (6 * 2 * 0.08^-1.6 = 682.9) and the parent the A/M law
    f = sample_breakup("explosion", 0.08, np.random.default_rng(31), parent="rocket_body", scaling=2.0)
    assert len(f) == 682
    rng = np.random.default_rng(31)
    lc = sample_sizes(682, 0.08, "explosion", rng)
    chi = sample_area_to_mass(lc, rng, "rocket_body")
    dv = sample_delta_v(chi, "explosion", rng)
    assert np.array_equal(f.lc_m, lc) and np.array_equal(f.chi, chi) and np.array_equal(f.dv_m_s, dv)
    # collision of 1000 kg above 10 cm: 0.1 * 1000^0.75 * 0.1^-1.71 = 912.0 fragments
    assert len(sample_breakup("collision", 0.1, np.random.default_rng(1), mass_kg=1000.0)) == 912


def test_bad_input_names_the_parameter():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match=r"^lc_min_m must be a finite number > 0, got -1\.0$"):
        sample_sizes(3, -1.0, "explosion", rng)
    with pytest.raises(ValueError, match=r"^lc_min_m must be a finite number > 0, got 0\.0$"):
        sbm_count("explosion", 0.0)
    with pytest.raises(ValueError, match=r"^scaling must be a finite number > 0, got 0\.0$"):
        sbm_count("explosion", 0.1, scaling=0.0)
    with pytest.raises(ValueError, match=r"^mass_kg must be a finite number > 0, got -5\.0$"):
        sbm_count("collision", 0.1, mass_kg=-5.0)
    with pytest.raises(ValueError, match=r"^mass_kg \(> 0\) is required for a collision$"):
        sbm_count("collision", 0.1)
