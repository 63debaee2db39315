# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Binomial births, their Poisson limit, and undetected births (document 001, Eq. 31–43)
#
# Document 001 (Chakravorty, Faber, Hussein, Mishra) models births as a spatial binomial process:
# the field of view of volume $V$ is cut into $M$ pixels of volume $\bar V = V/M$, each of which
# spawns a target with probability $\alpha = \lambda_B \bar V$. It then states
#
# $$\binom{M}{n}\alpha^n(1-\alpha)^{M-n} = \frac{e^{-\lambda_B V}(\lambda_B V)^n}{n!} \qquad \text{(Eq. 32)}$$
#
# — which is a limit as $M \to \infty$, not an equality — and the approximation
# $\alpha^n (1-\alpha)^{M-n} \approx e^{-\lambda_B V}\lambda_B^n \bar V^n$ (Eq. 33). From these it derives the
# weight ratio of a hypothesis with one undetected birth to its twin without it,
# $(1-p_D)\alpha$ (Eq. 39), and the bound $\omega^\gamma/\omega^{\gamma'} < 1 - p_D$ (Eq. 43) one scan later.
#
# This notebook:
#
# 1. proves the limit of Eq. 32 and finds its leading error term
#    $\ln\frac{\mathrm{Bin}}{\mathrm{Pois}} = -\frac{(n-\lambda V)^2 - n}{2M} + O(M^{-2})$, symbolically in $n$;
# 2. does the same for Eq. 33: ratio $\to 1$ with error $\frac{n\lambda V - (\lambda V)^2/2}{M}$;
# 3. plots the total-variation distance between $\mathrm{Bin}(M, \lambda V/M)$ and
#    $\mathrm{Poisson}(\lambda V)$ against $M$, with its exact asymptote $\mathbb E|(K-\lambda V)^2 - K|/(4M)$;
# 4. derives Eq. 39 from Eq. 37–38, and shows it is exact only under Eq. 33: with the exact binomial
#    factor of Eq. 31 the ratio is $(1-p_D)\alpha/(1-\alpha)$;
# 5. examines Eq. 43 for Gaussian birth pdfs: it holds at every return for the paper's uniform
#    pixel births, but for a Gaussian birth pdf it holds only under conditions the paper does not
#    state — shown, not hidden.

# %%
import math

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp
from scipy.stats import binom, poisson

from _common import Findings, formula

findings = Findings("birth_poisson_limit", "document 001 (Chakravorty et al.): Eq. 31-33, 37-43")

M, lamV, alpha, eps = sp.symbols("M lambdaV alpha epsilon", positive=True)
n = sp.symbols("n", integer=True, nonnegative=True)


@formula
def binomial_birth_probability(M, n, a):
    """Document 001 Eq. 32, left side: probability of n births among M pixels, alpha = a / M."""
    return sp.binomial(M, n) * (a / M) ** n * (1 - a / M) ** (M - n)


def poisson_probability(n, a):
    return sp.exp(-a) * a**n / sp.factorial(n)


# %% [markdown]
# ## 1. Eq. 32 is a limit: proof and leading error term
#
# With $\varepsilon = 1/M$, $\ln\frac{\mathrm{Bin}}{\mathrm{Pois}} = \sum_{i<n}\ln(1 - i\varepsilon)
# + (1/\varepsilon - n)\ln(1 - \lambda V\varepsilon) + \lambda V$. Its Taylor series in $\varepsilon$
# starts at order 1 — so the ratio tends to 1 (the limit) — with coefficient
# $-n(n-1)/2 + n\lambda V - (\lambda V)^2/2 = -[(n - \lambda V)^2 - n]/2$. Sympy derives the coefficient
# for symbolic $n$ (summing the first-order terms of the finite sum) and, independently, expands
# the binomial pmf itself for $n = 0..8$.

# %%
i = sp.symbols("i", integer=True, nonnegative=True)
first_order_falling = sp.summation(sp.diff(sp.log(1 - i * eps), eps).subs(eps, 0), (i, 0, n - 1))
power_part = sp.series((1 / eps - n) * sp.log(1 - lamV * eps) + lamV, eps, 0, 2).removeO()
log_ratio_first_order = sp.expand(first_order_falling + power_part.coeff(eps, 1))
leading_term = -((n - lamV) ** 2 - n) / 2
findings.check(
    "Eq. 32: the log-ratio Bin/Poisson has no O(1) term (the limit holds) for symbolic n",
    sp.simplify(power_part.coeff(eps, 0)) == 0,
)
findings.check(
    "Eq. 32: leading term of ln(Bin/Poisson) is -[(n - lambdaV)^2 - n] / (2M) for symbolic n",
    sp.simplify(log_ratio_first_order - leading_term) == 0,
    derived=str(sp.factor(log_ratio_first_order)),
)
direct_ok = []
for n_val in range(9):
    pmf_ratio = sp.expand_func(binomial_birth_probability(1 / eps, n_val, lamV)) / poisson_probability(n_val, lamV)
    direct = sp.series(sp.log(pmf_ratio), eps, 0, 2).removeO()
    direct_ok.append(sp.simplify(direct - leading_term.subs(n, n_val) * eps) == 0)
findings.check("Eq. 32: the direct series of the binomial pmf confirms the leading term for n = 0..8", all(direct_ok))
for n_val in (0, 1):
    limit = sp.limit(binomial_birth_probability(M, n_val, lamV), M, sp.oo)
    findings.check(f"Eq. 32: sympy.limit of the binomial pmf is the Poisson pmf for n = {n_val}",
                   sp.simplify(limit - poisson_probability(n_val, lamV)) == 0)
findings.record("eq32_leading_log_error", "-((n - lambdaV)^2 - n) / (2 M)")
# negative control: the Poisson pmf without its normalising e^(-lambda V) under the same limit check (n = 0)
unnormalised_limit = sp.limit(binomial_birth_probability(M, 0, lamV), M, sp.oo)
unnormalised_passes = sp.simplify(unnormalised_limit - poisson_probability(0, lamV) * sp.exp(lamV)) == 0
findings.claim("Eq. 32: binomial births = Poisson births", "001 Eq. 32", "equality",
               "limit M -> oo; ln(Bin/Pois) = -[(n - lambda V)^2 - n]/(2M) + O(M^-2)", "qualitative",
               note="an equality only in the limit; TV distance ~ E|(K - lambda V)^2 - K| / (4M)", key="eq32_poisson_limit",
               control=("the Poisson pmf without its normalising e^(-λV), limit at n = 0",
                        f"binomial limit {unnormalised_limit} vs 1", unnormalised_passes))

# %% [markdown]
# ## 2. Eq. 33: the approximation of the birth-hypothesis probability
#
# $\frac{\alpha^n(1-\alpha)^{M-n}}{e^{-\lambda_B V}\lambda_B^n\bar V^n} = (1 - \lambda V/M)^{M-n} e^{\lambda V}$ with
# $\alpha = \lambda_B\bar V$, $\bar V = V/M$ (write $\lambda V$ for $\lambda_B V$). Its logarithm is
# $\frac{n\lambda V - (\lambda V)^2/2}{M} + O(M^{-2})$: the ratio tends to 1, but for fixed $M$ the
# approximation is off by a factor that grows with the number of births $n$.

# %%
@formula
def eq33_ratio(M, n, a):
    """Document 001 Eq. 33: exact alpha^n (1 - alpha)^(M - n) over its approximation, alpha = a / M."""
    return (a / M) ** n * (1 - a / M) ** (M - n) / (sp.exp(-a) * (a / M) ** n)


eq33_log = sp.series(sp.log(eq33_ratio(1 / eps, n, lamV)), eps, 0, 3).removeO()
findings.check("Eq. 33: ratio -> 1 (no O(1) term in its log), symbolic n", sp.simplify(eq33_log.coeff(eps, 0)) == 0)
findings.check(
    "Eq. 33: leading term of the log-ratio is (n lambdaV - lambdaV^2 / 2) / M, symbolic n",
    sp.simplify(eq33_log.coeff(eps, 1) - (n * lamV - lamV**2 / 2)) == 0,
    second_order=str(sp.factor(eq33_log.coeff(eps, 2))),
)
findings.record("eq33_log_ratio_series", str(sp.expand(eq33_log)))

# %% [markdown]
# ## 3. Total-variation distance between Bin(M, λV/M) and Poisson(λV)
#
# From the leading term above, $\mathrm{Bin}(k) = \mathrm{Pois}(k)\,[1 - ((k-\lambda V)^2 - k)/(2M)] + O(M^{-2})$,
# so $M\cdot d_{TV} \to \tfrac14\mathbb E_{\mathrm{Pois}}|(K-\lambda V)^2 - K|$. The distance is computed
# from scipy's pmfs (tails included) and must also respect the Barbour–Hall bound
# $d_{TV} \le (1 - e^{-\lambda V})\lambda V/M$.

# %%
def tv_distance(M_pixels: int, a: float) -> float:
    k_max = min(M_pixels, int(a + 40 * math.sqrt(a) + 40))
    k = np.arange(k_max + 1)
    diff = np.abs(binom.pmf(k, M_pixels, a / M_pixels) - poisson.pmf(k, a)).sum()
    return 0.5 * (diff + poisson.sf(k_max, a) + binom.sf(k_max, M_pixels, a / M_pixels))


def tv_asymptote_constant(a: float) -> float:
    k = np.arange(int(a + 60 * math.sqrt(a) + 60))
    return float((poisson.pmf(k, a) * np.abs((k - a) ** 2 - k)).sum() / 4)


RATES = (0.5, 2.0, 10.0)
M_GRID = np.unique(np.round(np.logspace(np.log10(20), 7, 25)).astype(int))
tv_rows = []
for a in RATES:
    const = tv_asymptote_constant(a)
    for M_pix in M_GRID:
        tv = tv_distance(int(M_pix), a)
        tv_rows.append({"lambdaV": a, "M": int(M_pix), "tv": tv, "M_times_tv": M_pix * tv, "asymptote_constant": const,
                        "barbour_hall_bound": (1 - math.exp(-a)) * a / M_pix})

for a in RATES:
    rows = [r for r in tv_rows if r["lambdaV"] == a]
    findings.check(f"TV(Bin, Poisson) decreases monotonically in M (lambdaV = {a})",
                   all(r2["tv"] < r1["tv"] for r1, r2 in zip(rows, rows[1:])))
    findings.check(f"TV(Bin, Poisson) <= Barbour-Hall bound (1 - e^-lambdaV) lambdaV / M at every M (lambdaV = {a})",
                   all(r["tv"] <= r["barbour_hall_bound"] for r in rows))
    findings.check(
        f"M * TV -> E|(K - lambdaV)^2 - K| / 4 within 1e-5 relative at M = 1e7 (lambdaV = {a})",
        abs(rows[-1]["M_times_tv"] / rows[-1]["asymptote_constant"] - 1) < 1e-5,
        M_times_tv=rows[-1]["M_times_tv"], constant=rows[-1]["asymptote_constant"],
    )
findings.record("tv_table", tv_rows)

fig, ax = plt.subplots(figsize=(6.5, 5.0))
for a, color in zip(RATES, ("C0", "C1", "C2")):
    rows = [r for r in tv_rows if r["lambdaV"] == a]
    Ms = np.array([r["M"] for r in rows])
    ax.loglog(Ms, [r["tv"] for r in rows], "o", color=color, ms=4, label=f"TV, λV = {a}")
    ax.loglog(Ms, rows[0]["asymptote_constant"] / Ms, "-", color=color, lw=1,
              label=r"asymptote $\mathbb{E}|(K-\lambda V)^2-K|/(4M)$" if a == RATES[0] else None)
    ax.loglog(Ms, [r["barbour_hall_bound"] for r in rows], ":", color=color, lw=1,
              label=r"Barbour–Hall bound $(1-e^{-\lambda V})\lambda V/M$" if a == RATES[0] else None)
ax.set_xlabel("number of birth pixels M (count)")
ax.set_ylabel("total-variation distance (probability)")
ax.set_title("Binomial births → Poisson births (document 001 Eq. 32)")
# below the axes: the lines cross the lower-left corner at large λV, so no corner of the data is empty
ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, frameon=False)
fig.tight_layout()
findings.figure(fig, "tv_distance")
plt.show()

# %% [markdown]
# ## 4. The undetected-birth ratio, Eq. 37–39
#
# Hypothesis $v$ has $n$ targets, $n - r$ of them births of which $s = n - r - 1$ are detected;
# its twin $v'$ is identical without the undetected birth. Eq. 37 and 38 (with their free
# exponents kept symbolic) give $\omega_v / \omega_{v'} = (1 - p_D)\lambda_B\bar V = (1-p_D)\alpha$ (Eq. 39).
# Eq. 37–38 use the approximation Eq. 33; with the exact binomial factor
# $\alpha^{n-r}(1-\alpha)^{M-(n-r)}$ of Eq. 31 the ratio is $(1-p_D)\alpha/(1-\alpha)$, i.e. Eq. 39 is
# low by the relative amount $\alpha/(1-\alpha)$.

# %%
p_D, lam_B, Vbar, lam_C, eta, A, w_q = sp.symbols("p_D lambda_B Vbar lambda_C eta A omega_q", positive=True)
n_, r_, m_, k_ = sp.symbols("n r m k", integer=True, nonnegative=True)
s_ = n_ - r_ - 1


@formula
def eq37_weight(n, r, s):
    """Document 001 Eq. 37: FISST weight of an n-target hypothesis with n - r births, s of them detected."""
    return (eta * (1 - p_D) ** (n - (m_ - k_)) * p_D ** (m_ - k_) * A * lam_B ** (n - r)
            * Vbar ** ((n - r) - s) * lam_C**k_ * w_q)


ratio_39 = sp.powsimp(sp.simplify(eq37_weight(n_, r_, s_) / eq37_weight(n_ - 1, r_, s_)), force=True)
findings.check(
    "Eq. 39: omega_v / omega_v' = (1 - p_D) lambda_B Vbar = (1 - p_D) alpha from Eq. 37-38",
    sp.simplify(ratio_39.subs(lam_B, alpha / Vbar) - (1 - p_D) * alpha) == 0,
    derived=str(ratio_39),
)
M_pix = sp.symbols("M_pix", integer=True, positive=True)
binomial_factor = alpha ** (n_ - r_) * (1 - alpha) ** (M_pix - (n_ - r_))
exact_ratio = sp.simplify((1 - p_D) * binomial_factor / binomial_factor.subs(n_, n_ - 1))
findings.check(
    "with Eq. 31's exact binomial birth factor the ratio is (1 - p_D) alpha / (1 - alpha)",
    sp.simplify(exact_ratio - (1 - p_D) * alpha / (1 - alpha)) == 0,
    derived=str(exact_ratio),
)
findings.record("eq39_ratio", "(1 - p_D) * alpha")
# negative control: Eq. 37 without its missed-detection factor (1 - p_D)^(n - (m - k)) gives a ratio of alpha alone
ratio_no_miss = sp.simplify((eq37_weight(n_, r_, s_) / (1 - p_D) ** (n_ - (m_ - k_)))
                            / (eq37_weight(n_ - 1, r_, s_) / (1 - p_D) ** (n_ - 1 - (m_ - k_)))).subs(lam_B, alpha / Vbar)
findings.claim("Eq. 39: undetected-birth weight ratio", "001 Eq. 37-39", "(1 - p_D) alpha", str(ratio_39.subs(lam_B, alpha / Vbar)),
               "reproduced",
               control=("Eq. 37 without its missed-detection factor (1 - p_D)^(n - (m - k))", str(sp.simplify(ratio_no_miss)),
                        sp.simplify(ratio_no_miss - (1 - p_D) * alpha) == 0), note="exact under the Eq. 33 approximation; the exact binomial factor of Eq. 31 gives "
                                  "(1 - p_D) alpha / (1 - alpha)", key="eq39_ratio")
findings.record("eq31_exact_ratio", "(1 - p_D) * alpha / (1 - alpha)")

# %% [markdown]
# ## 5. Eq. 42–43: one scan later, with Gaussian birth pdfs
#
# The undetected birth's pdf is predicted ($x' = x + w$, $w \sim \mathcal N(0, Q)$) and then produces
# the return $z^* = x + v$, $v \sim \mathcal N(0, R)$ (1-D, enough to show the structure). Eq. 40–42 give
#
# $$\frac{\omega^\gamma}{\omega^{\gamma'}} = \frac{\int p(z^*|x)p_b^-(x)dx}{\lambda_B}(1-p_D)\alpha
#   = (1-p_D)\,\bar V \int p(z^*|x)\,p_b^-(x)\,dx,$$
#
# and Eq. 43 claims this is $< 1 - p_D$, i.e. $\int p(z^*|x)p_b^-(x)dx < 1/\bar V$.
#
# * **Uniform pixel birth** (the paper's Eq. 31 model, pixel $[c - \bar V/2, c + \bar V/2]$):
#   $\bar V\int p(z^*|x)p_b^-(x)dx = \tfrac12[\mathrm{erf}(\frac{z^*-c+\bar V/2}{\sqrt{2(Q+R)}}) -
#   \mathrm{erf}(\frac{z^*-c-\bar V/2}{\sqrt{2(Q+R)}})]$, at most $\mathrm{erf}(\bar V/(2\sqrt{2(Q+R)})) < 1$:
#   **Eq. 43 holds at every return.**
# * **Gaussian birth pdf** $\mathcal N(c, P)$: the same quantity is $\bar V\,\mathcal N(z^*; c, P+Q+R)$,
#   whose maximum $\bar V/\sqrt{2\pi(P+Q+R)}$ is below 1 only if $2\pi(P+Q+R) > \bar V^2$. A
#   Gaussian matched to the pixel by *peak height* ($P = \bar V^2/2\pi$) satisfies this strictly.
#   One matched by *variance* ($P = \bar V^2/12$) peaks at $\sqrt{6/\pi}\sqrt{P/(P+Q+R)}$, which
#   **exceeds 1 when $Q + R < (6/\pi - 1)P$** — Eq. 43 then fails near the pixel centre.
# * **Gaussian new birth as well** (the comparison the paper's Fig. 10 draws: the new-birth
#   likelihood $\mathcal N(z^*; c, P+R)$ replaces $1/\bar V$): the ratio over $1-p_D$ is
#   $\mathcal N(z^*; c, P+Q+R)/\mathcal N(z^*; c, P+R)$, equal to $\sqrt{a/b} < 1$ at the centre
#   ($a = P+R$, $b = P+Q+R$) and below 1 exactly when $(z^*-c)^2 < ab\ln(b/a)/(b-a)$.

# %%
z, x, c = sp.symbols("z x c", real=True)
Pp, Q, R, var_pred = sp.symbols("P Q R u", positive=True)


def gauss(arg, mean, var):
    return sp.exp(-((arg - mean) ** 2) / (2 * var)) / sp.sqrt(2 * sp.pi * var)


predictive = sp.integrate(gauss(z, x, R) * gauss(x, c, var_pred), (x, -sp.oo, sp.oo), conds="none")
findings.check(
    "int N(z; x, R) N(x; c, u) dx = N(z; c, u + R) (predicted Gaussian birth, symbolic)",
    sp.simplify(sp.expand_log(sp.log(predictive / gauss(z, c, var_pred + R)), force=True)) == 0,
)

s_noise = sp.symbols("s", positive=True)  # sqrt(Q + R)
uniform_pred = sp.integrate(gauss(z, x, s_noise**2) / Vbar, (x, c - Vbar / 2, c + Vbar / 2), conds="none")
erf_form = (sp.erf((z - c + Vbar / 2) / (sp.sqrt(2) * s_noise)) - sp.erf((z - c - Vbar / 2) / (sp.sqrt(2) * s_noise))) / 2
findings.check(
    "uniform pixel birth: Vbar * int p(z*|x) p_b^-(x) dx = [erf(..) - erf(..)] / 2 (symbolic)",
    sp.simplify(Vbar * uniform_pred - erf_form) == 0,
)
centre_value = sp.simplify(erf_form.subs(z, c))
slope_at_centre = sp.simplify(sp.diff(erf_form, z).subs(z, c))
curvature_at_centre = sp.simplify(sp.diff(erf_form, z, 2).subs(z, c))
findings.check(
    "uniform pixel birth: the ratio peaks at the pixel centre with value erf(Vbar / (2 sqrt(2) s)) < 1 "
    "(Eq. 43 holds for every return)",
    slope_at_centre == 0 and curvature_at_centre.is_negative
    and sp.simplify(centre_value - sp.erf(Vbar / (2 * sp.sqrt(2) * s_noise))) == 0,
    centre=str(centre_value),
)
findings.check(
    "uniform pixel birth: the ratio (over 1 - p_D) is strictly below 1 at the centre for every noise level",
    # 1 - erf(x) = erfc(x) > 0 for finite x; 50 digits so that the tiny margins are resolved.
    all(sp.N(1 - centre_value.subs({Vbar: 1, s_noise: sv}), 50) > 0 for sv in (0.05, 0.1, 1, 10)),
)

gauss_peak = Vbar * gauss(c, c, Pp + Q + R)  # ratio over (1 - p_D) at z* = c
peak_matched = sp.simplify(gauss_peak.subs(Pp, Vbar**2 / (2 * sp.pi)))
findings.check(
    "Gaussian birth matched by peak height (P = Vbar^2 / 2 pi): centre ratio = sqrt(P / (P + Q + R)) < 1",
    sp.simplify(peak_matched**2 - (Vbar**2 / (2 * sp.pi)) / (Vbar**2 / (2 * sp.pi) + Q + R)) == 0,
)
variance_matched = sp.simplify(gauss_peak.subs(Pp, Vbar**2 / 12))
threshold = sp.solve(sp.Eq(variance_matched**2, 1), Q)
findings.check(
    "Gaussian birth matched by variance (P = Vbar^2 / 12): Eq. 43 fails at the centre iff Q + R < (6/pi - 1) P",
    len(threshold) == 1 and sp.simplify(threshold[0] + R - (6 / sp.pi - 1) * Vbar**2 / 12) == 0,
    threshold_Q=str(threshold),
)
counter_example = float(variance_matched.subs({Vbar: 1, Q: 0.005, R: 0.005}))
findings.check(
    "counter-example: Vbar = 1, P = 1/12, Q = R = 0.005 gives omega_gamma / omega_gamma' = "
    f"{counter_example:.3f} (1 - p_D) > (1 - p_D)",
    counter_example > 1,
)
findings.claim("Eq. 43 bound, uniform pixel births", "001 Eq. 42-43", "< 1 - p_D",
               "<= (1 - p_D) erf(Vbar / (2 sqrt(2 (Q + R))))", "reproduced", note="at every return z*", key="eq43_uniform",
               control=("the same bound with a variance-matched Gaussian birth pdf (Q = R = 0.005 Vbar²)",
                        f"{counter_example:.3f} (1 - p_D)", counter_example < 1))
findings.claim("Eq. 43 bound, Gaussian birth pdfs", "001 Eq. 42-43, Fig. 10", "< 1 - p_D",
               f"{counter_example:.3f} (1 - p_D) for a variance-matched Gaussian, Q = R = 0.005 Vbar^2",
               "reproduced" if counter_example < 1 else "not reproduced",
               note="holds if the birth Gaussian's peak density is <= 1/Vbar, or (Gaussian new birth) within "
                    "d^2 < ab ln(b/a)/(b - a) of the pixel centre; fails otherwise", key="eq43_gaussian",
               cause="document")
findings.record("eq43_variance_matched_counterexample", {"Vbar": 1, "P": 1 / 12, "Q": 0.005, "R": 0.005,
                                                           "ratio_over_1_minus_pD": counter_example})

a_, b_, d_ = sp.symbols("a b d", positive=True)
log_gg = sp.expand_log(sp.log(gauss(d_, 0, b_) / gauss(d_, 0, a_)), force=True)
# The log-ratio's second derivative in d is 1/a - 1/b > 0 (b > a): it grows with |d|, so the ratio
# is below 1 inside the crossing radius and above 1 outside it.
crossing = {sp.simplify(root**2) for root in sp.solve(sp.Eq(log_gg, 0), d_)}
findings.check(
    "Gaussian new birth: ratio over (1 - p_D) is sqrt(a/b) < 1 at the centre and < 1 iff d^2 < a b ln(b/a) / (b - a)",
    sp.simplify(sp.exp(log_gg.subs(d_, 0)) - sp.sqrt(a_ / b_)) == 0
    and len(crossing) == 1
    and sp.simplify(sp.expand_log(crossing.pop() - a_ * b_ * sp.log(b_ / a_) / (b_ - a_), force=True)) == 0
    and sp.simplify(sp.diff(log_gg, d_, 2) - (1 / a_ - 1 / b_)) == 0,
)
findings.record("eq43_gaussian_radius_squared", "a b ln(b/a) / (b - a), a = P + R, b = P + Q + R")

# %%
d_axis = np.linspace(-1.5, 1.5, 301)  # z* - c in pixel widths (Vbar = 1)
noise = {"Q": 0.005, "R": 0.005}
s_val = math.sqrt(noise["Q"] + noise["R"])
uniform_curve = sp.lambdify(z, erf_form.subs({c: 0, Vbar: 1, s_noise: s_val}), "scipy")(d_axis)


def gaussian_curve(P_val):
    var = P_val + noise["Q"] + noise["R"]
    return np.exp(-(d_axis**2) / (2 * var)) / np.sqrt(2 * np.pi * var)


gauss_gauss = gaussian_curve(1 / 12) / (np.exp(-(d_axis**2) / (2 * (1 / 12 + noise["R"])))
                                         / np.sqrt(2 * np.pi * (1 / 12 + noise["R"])))
# The new birth sits in the pixel that holds z*, so that comparison only means something inside it.
gauss_gauss[np.abs(d_axis) > 0.5] = np.nan
fig, ax = plt.subplots(figsize=(6.5, 5.2))
ax.axvspan(-0.5, 0.5, color="0.92", label="birth pixel")
ax.plot(d_axis, uniform_curve, "k-", label="uniform pixel birth (document 001 Eq. 31)")
ax.plot(d_axis, gaussian_curve(1 / (2 * np.pi)), "C0--", label=r"Gaussian birth, peak-matched $P=(\bar{V})^2/2\pi$")
ax.plot(d_axis, gaussian_curve(1 / 12), "C3-.", label=r"Gaussian birth, variance-matched $P=(\bar{V})^2/12$")
ax.plot(d_axis, gauss_gauss, "C2:", label="Gaussian birth vs Gaussian new birth, variance-matched (Fig. 10)")
ax.axhline(1.0, color="grey", lw=0.8)
ax.text(-1.45, 1.03, "Eq. 43 bound", color="grey")
ax.set_ylim(0, 2)
ax.set_xlabel(r"return offset from the pixel centre $(z^*-c)/\bar V$ (pixel widths)")
ax.set_ylabel(r"$\omega^\gamma / \omega^{\gamma'}$ divided by $(1-p_D)$ (dimensionless)")
ax.set_title(r"Eq. 43 one scan after an undetected birth, $Q = R = 0.005\,(\bar{V})^2$")
# below the axes: the curves fill the upper left, where a legend inside would cover them
ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1, frameon=False)
fig.tight_layout()
findings.figure(fig, "eq43")
plt.show()

# %%
findings.write()
