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
# # Do the multi-target likelihoods normalise? (document 000 Eq. 8–9, 20, 39; document 001 Eq. 5–7)
#
# Document 000 (H-FISST) gives each child $j$ of an $M$-object parent, in which $k$ objects are
# detected among $m$ returns, the prior probability
#
# $$p_{ij} = \frac{p_D^k (1-p_D)^{M-k}}{\binom{m}{k} k!} \qquad \text{(Eq. 8)}$$
#
# and claims $\sum_j p_{ij} = 1$ (Eq. 9), "assuming $M < m$". Yet Sec. II opens with the
# opposite assumption — "the number of measurements is always less than the number of
# objects, which is typically the case in the SSA problem". The two cannot both hold, and
# the sum is 1 only under the second-quoted one:
#
# $$\sum_j p_{ij} = \sum_{k=0}^{\min(M,m)} \binom{M}{k} p_D^k (1-p_D)^{M-k}
#   = \begin{cases} 1 & M \le m \\ P[\mathrm{Bin}(M, p_D) \le m] & M > m. \end{cases}$$
#
# The missing mass $P[\mathrm{Bin}(M,p_D) > m]$ belongs to detection patterns that would
# need more returns than were received: Eq. 8 never conditions on the number of returns.
# This notebook shows the identity exactly, then checks that Eq. 20 (the integral of the
# multi-target likelihood) inherits it, that the two-target appendix likelihood Eq. 39 is the
# $M = m = 2$ case and integrates to 1, and that document 001's Poisson-clutter likelihood
# (Eq. 5–7) is a proper set density — its set integral, with the $1/m!$ factor, is 1.

# %%
import math
from collections import Counter

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp
from scipy.stats import binom, poisson

from _common import Findings, association_events, formula, integrate_sum_of_products

findings = Findings(
    "likelihood_normalisation",
    "document 000 Eq. 8-9, 20, 39 (appendix); document 001 Eq. 5-7, 18, 30",
)
p_D = sp.symbols("p_D", positive=True)


@formula
def eq8_prior(M: int, m: int, k: int, p):
    """Document 000 Eq. 8: prior probability of one child with k of M objects detected among m returns."""
    return p**k * (1 - p) ** (M - k) / (sp.binomial(m, k) * sp.factorial(k))


def binomial_cdf(M: int, m: int, p):
    return sum(sp.binomial(M, k) * p**k * (1 - p) ** (M - k) for k in range(min(M, m) + 1))


# %% [markdown]
# ## 1. Eq. 9 over brute-force enumerated children
#
# The children are enumerated (every feasible association event, as in the
# `hypothesis_count` notebook); each contributes Eq. 8 with its own number of detections $k$.
# The sum is compared, as a polynomial in $p_D$, with 1 and with the binomial CDF.

# %%
N_MAX = 6
eq9_rows = []
for M in range(N_MAX + 1):
    for m in range(N_MAX + 1):
        detections = Counter(sum(1 for j in event if j >= 0) for event in association_events(M, m))
        total = sp.expand(sum(n_children * eq8_prior(M, m, k, p_D) for k, n_children in detections.items()))
        eq9_rows.append((M, m, total))

findings.check(
    f"Eq. 9: sum_j p_ij = 1 exactly (as a polynomial in p_D) for all M <= m <= {N_MAX}",
    all(sp.expand(total - 1) == 0 for M, m, total in eq9_rows if M <= m),
)
findings.check(
    f"Eq. 9 fails for M > m: sum_j p_ij = P[Bin(M, p_D) <= m] exactly for all m < M <= {N_MAX}",
    all(sp.expand(total - binomial_cdf(M, m, p_D)) == 0 for M, m, total in eq9_rows if M > m),
)
findings.check(
    f"... the lost mass 1 - sum_j p_ij is P[Bin(M, p_D) > m], positive for p_D in (0, 1] (m < M <= {N_MAX})",
    all(sp.expand(1 - total) == sp.expand(sum(sp.binomial(M, k) * p_D**k * (1 - p_D) ** (M - k)
                                                for k in range(m + 1, M + 1)))
        for M, m, total in eq9_rows if M > m),
)

# %% [markdown]
# How large is the defect in the SSA regime the paper targets ($m < M$, $p_D = 0.95$)?
# For ten objects and five returns the children's prior probabilities sum to
# $P[\mathrm{Bin}(10, 0.95) \le 5] \approx 6\times 10^{-5}$, not 1.

# %%
defect_10_5 = binomial_cdf(10, 5, sp.Rational(95, 100))
findings.check(
    "Eq. 9 at M=10, m=5, p_D=0.95 equals scipy's binom.cdf(5, 10, 0.95)",
    abs(float(defect_10_5) - binom.cdf(5, 10, 0.95)) < 1e-15,
    exact=defect_10_5,
)
findings.record("eq9_sum_M10_m5_pD095_exact", defect_10_5)
findings.record("eq9_sum_M10_m5_pD095", float(defect_10_5))
findings.claim("Eq. 9: children's prior probabilities sum to 1", "000 Eq. 8-9", "1",
               f"P[Bin(M, p_D) <= m]; {float(defect_10_5):.3g} at M=10, m=5, p_D=0.95",
               "reproduced" if float(defect_10_5) == 1 else "not reproduced",
               note="exactly 1 only when M <= m; the text assumes both M < m (Eq. 9) and m < M (Sec. II)", key="eq9_prior_sum",
               cause="document")
print("sum_j p_ij at M=10, m=5, p_D=0.95:", float(defect_10_5))

# %%
P_SHOW = 0.95
grid = np.array([[binom.cdf(m, M, P_SHOW) for m in range(13)] for M in range(13)])
fig, (ax, ax2) = plt.subplots(2, 1, figsize=(6.5, 6.9))  # the report's line width: 10 pt text prints at 10 pt
im = ax.imshow(np.log10(grid), origin="lower", cmap="viridis")
ax.plot([-0.5, 12.5], [-0.5, 12.5], "w--", lw=0.8)
ax.text(8.5, 3, "M ≤ m: sum = 1", color="k", ha="center", fontsize=9)
ax.text(3, 9.5, "M > m:\nsum < 1", color="w", ha="center")
ax.set_xlabel("returns m")
ax.set_ylabel("objects M")
ax.set_xticks(range(0, 13, 2))
ax.set_title(r"$\log_{10}\sum_j p_{ij}$ (Eq. 9) at $p_D$ = 0.95")
fig.colorbar(im, ax=ax, label=r"$\log_{10}$ of the sum (0 means normalised)")
for p_show, style in ((0.5, "C0"), (0.9, "C1"), (0.95, "C2"), (0.99, "C3")):
    ax2.semilogy(range(13), [binom.cdf(m, 10, p_show) for m in range(13)], "o-", color=style, ms=3,
                 label=f"$p_D$ = {p_show}")
ax2.axvline(10, color="grey", lw=0.8)
ax2.text(10.2, 1e-12, "m = M", color="grey")
ax2.set_xlabel("returns m")
ax2.set_ylabel(r"$\sum_j p_{ij}$ = P[Bin(10, $p_D$) ≤ m] (probability)")
ax2.set_title("M = 10 objects: Eq. 9 holds only for m ≥ M")
ax2.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)  # the curves fill the axes
fig.tight_layout()
findings.figure(fig, "eq9")
plt.show()

# %% [markdown]
# ## 2. Eq. 20: integrating the multi-target likelihood
#
# With Gaussian single-target likelihoods $p(z \mid x) = \mathcal N(z; x, \sigma^2)$ and clutter
# uniform on $[0, V]$, Eq. 20 is $\int \sum_j p_{ij} \prod_l p(z_l \mid X_{j_l})\,dz_1 \cdots dz_m$.
# Each product integrates to 1, so the integral equals $\sum_j p_{ij}$: exactly 1 for
# $M = m = 2$ (and $M = 1 < m = 2$), but $1 - p_D^3 = P[\mathrm{Bin}(3, p_D) \le 2]$ for
# $M = 3 > m = 2$. The integrals are done by Sympy with $x_j$, $\sigma$, $V$, $p_D$ symbolic.

# %%
sigma, V = sp.symbols("sigma V", positive=True)
zs = sp.symbols("z1:5", real=True)
xs = sp.symbols("x1:4", real=True)


def gauss(z, x):
    return sp.exp(-((z - x) ** 2) / (2 * sigma**2)) / sp.sqrt(2 * sp.pi * sigma**2)


def in_view(z):
    return sp.Piecewise((1, (z >= 0) & (z <= V)), (0, True))


def clutter(z):
    return in_view(z) / V


def eq20_integrand(M: int, m: int):
    """Document 000 Eq. 20 integrand: sum over children of Eq. 8 times Eq. 13 (with clutter, Eq. 18)."""
    total = sp.Integer(0)
    for event in association_events(M, m):
        k = sum(1 for j in event if j >= 0)
        lik = sp.Mul(*[gauss(zs[i], xs[j]) if j >= 0 else clutter(zs[i]) for i, j in enumerate(event)])
        total += eq8_prior(M, m, k, p_D) * lik
    return total


eq20 = {(M, m): integrate_sum_of_products(eq20_integrand(M, m), zs[:m]) for M, m in ((2, 2), (1, 2), (3, 2))}
findings.check("Eq. 20 integrates to 1 for M = m = 2 (symbolic)", sp.simplify(eq20[2, 2] - 1) == 0, value=eq20[2, 2])
findings.check("Eq. 20 integrates to 1 for M = 1 < m = 2 (symbolic)", sp.simplify(eq20[1, 2] - 1) == 0)
findings.check(
    "Eq. 20 integrates to 1 - p_D^3 = P[Bin(3, p_D) <= 2] for M = 3 > m = 2 (symbolic)",
    sp.simplify(eq20[3, 2] - (1 - p_D**3)) == 0,
    value=eq20[3, 2],
)
findings.record("eq20_integral", {f"M={M},m={m}": str(v) for (M, m), v in eq20.items()})
findings.claim("Eq. 20: the multi-target likelihood integrates to 1", "000 Eq. 20", "1",
               f"1 for M <= m; {eq20[3, 2]} for M=3, m=2", "not reproduced",
               note="inherits the Eq. 9 defect: the integral equals P[Bin(M, p_D) <= m]", key="eq20_integral",
               cause="document")

# %% [markdown]
# ## 3. The appendix's two-target likelihood (Eq. 39)
#
# $$p(\{z_1,z_2\}\mid\{x_1,x_2\}) = \tfrac{p_D^2}{2}\{p(z_1|x_1)p(z_2|x_2) + p(z_1|x_2)p(z_2|x_1)\}
#  + \tfrac{p_D(1-p_D)}{2}\{\ldots\} + (1-p_D)^2 g(z_1)g(z_2).$$
#
# It is term for term the $M = m = 2$ integrand of Eq. 20, and its ordinary double integral is 1.
# Its FISST *set* integral restricted to $|Z| = 2$ carries a $1/2!$ and is therefore $1/2$:
# Eq. 39 is normalised as a density of the ordered pair $(z_1, z_2)$ given that two returns
# arrived, not as a set density over all cardinalities.

# %%
@formula
def eq39_likelihood(z1, z2, x1, x2, p):
    """Document 000 appendix Eq. 39, as printed."""
    return (
        p**2 / 2 * (gauss(z1, x1) * gauss(z2, x2) + gauss(z1, x2) * gauss(z2, x1))
        + p * (1 - p) / 2 * (gauss(z1, x1) * clutter(z2) + gauss(z2, x1) * clutter(z1))
        + p * (1 - p) / 2 * (gauss(z1, x2) * clutter(z2) + gauss(z2, x2) * clutter(z1))
        + (1 - p) ** 2 * clutter(z1) * clutter(z2)
    )


eq39 = eq39_likelihood(zs[0], zs[1], xs[0], xs[1], p_D)
findings.check(
    "Eq. 39 equals the Eq. 20 integrand for M = m = 2 (symbolic identity)",
    sp.expand(eq39 - eq20_integrand(2, 2)) == 0,
)
eq39_integral = integrate_sum_of_products(eq39, zs[:2])
findings.check("Eq. 39 integrates to 1 over (z1, z2) (symbolic)", sp.simplify(eq39_integral - 1) == 0,
               value=eq39_integral)
findings.check("Eq. 39's set integral over |Z| = 2 is 1/2! = 1/2", sp.simplify(eq39_integral / 2 - sp.Rational(1, 2)) == 0)
# negative control: Eq. 39 without its normalising 1/2 on the two-detection term (the two orderings summed)
eq39_unhalved = eq39 + p_D**2 / 2 * (gauss(zs[0], xs[0]) * gauss(zs[1], xs[1]) + gauss(zs[0], xs[1]) * gauss(zs[1], xs[0]))
eq39_unhalved_integral = sp.simplify(integrate_sum_of_products(eq39_unhalved, zs[:2]))
findings.claim("Eq. 39: the two-target likelihood integrates to 1", "000 appendix Eq. 39", "1", str(eq39_integral),
               "reproduced" if eq39_integral == 1 else "not reproduced",
               note="symbolic; a density of the ordered pair (z1, z2) given two returns", key="eq39_integral",
               control=("Eq. 39 without the 1/2 of its two-detection term", str(eq39_unhalved_integral).replace("**2", "²"),
                        sp.simplify(eq39_unhalved_integral - 1) == 0))

# %% [markdown]
# ## 4. Document 001: the Poisson-clutter likelihood is a set density (Eq. 5–7)
#
# $p(Z \mid X, n) = \sum_\sigma p(\sigma \mid n)\, p(Z \mid \sigma, X, n)$ with
# $p(\sigma \mid n) = p_D^{m-k}(1-p_D)^{n-(m-k)} e^{-\lambda V}(\lambda V)^k/k!$ (Eq. 6) and
# $p(Z \mid \sigma, X, n) = \frac{k!}{V^k}\prod_i p(z_{\sigma_i} \mid x_i)$ (Eq. 7), $k$ being the number
# of clutter returns. The associations $\sigma$ are enumerated by brute force and the clutter
# returns carry the uniform density on the field of view $[0, V]$. The FISST set integral
#
# $$\int p(Z \mid X)\,\delta Z = \sum_{m \ge 0} \frac{1}{m!} \int p(\{z_1..z_m\} \mid X)\,dz_1 \cdots dz_m$$
#
# must be 1. Its $m$-th term is the probability of receiving $m$ returns, which must be the
# convolution of $\mathrm{Bin}(n, p_D)$ detections with $\mathrm{Poisson}(\lambda V)$ clutter; Sympy
# checks that for $n \le 3$, $m \le 4$ and then sums the series to infinity.

# %%
lam = sp.symbols("lambda", positive=True)


@formula
def eq6_association_prior(n: int, m: int, k: int, p):
    """Document 001 Eq. 6: prior of an association of n targets with k of the m returns clutter."""
    return p ** (m - k) * (1 - p) ** (n - (m - k)) * sp.exp(-lam * V) * (lam * V) ** k / sp.factorial(k)


def eq5_likelihood(n: int, m: int):
    """Document 001 Eq. 5 with Eq. 6-7: sum over associations sigma (brute force) of prior x likelihood."""
    total = sp.Integer(0)
    for event in association_events(n, m):  # event[i] = target of return i, or -1 for clutter
        k = sum(1 for j in event if j < 0)
        lik = sp.factorial(k) / V**k * sp.Mul(*[gauss(zs[i], xs[j]) if j >= 0 else in_view(zs[i])
                                                for i, j in enumerate(event)])
        total += eq6_association_prior(n, m, k, p_D) * lik
    return total


def cardinality_pmf(n: int, m: int):
    """P(|Z| = m): Bin(n, p_D) detections plus Poisson(lambda V) clutter."""
    return sum(sp.binomial(n, d) * p_D**d * (1 - p_D) ** (n - d) * sp.exp(-lam * V) * (lam * V) ** (m - d)
               / sp.factorial(m - d) for d in range(min(n, m) + 1))


set_terms = {(n, m): integrate_sum_of_products(eq5_likelihood(n, m), zs[:m]) for n in range(4) for m in range(5)}

bad_terms = [
    (n, m) for (n, m), value in set_terms.items()
    if sp.simplify(value / sp.factorial(m) - cardinality_pmf(n, m)) != 0
]
findings.check(
    "(1/m!) * integral of Eq. 5-7 over m returns = P[Bin(n,p_D) + Poisson(lambda V) = m] for n <= 3, m <= 4",
    not bad_terms,
    mismatches=bad_terms,
)
kk = sp.symbols("k", integer=True, nonnegative=True)
set_integrals = {}
for n in range(4):
    # Write m = d + k (d detections, k clutter) and sum k to infinity symbolically.
    series = sum(
        sp.binomial(n, d) * p_D**d * (1 - p_D) ** (n - d)
        * sp.summation(sp.exp(-lam * V) * (lam * V) ** kk / sp.factorial(kk), (kk, 0, sp.oo))
        for d in range(n + 1)
    )
    set_integrals[n] = sp.simplify(series)
findings.check(
    "the set integral sum_m (1/m!) int p(Z|X) dZ of document 001's likelihood is 1 for n = 0..3 targets",
    all(v == 1 for v in set_integrals.values()),
    values=set_integrals,
)
findings.check(
    "without the 1/m! factor the m = 2 term would be 2! P(|Z| = 2): the set-integral factor is needed",
    sp.simplify(set_terms[2, 2] - 2 * cardinality_pmf(2, 2)) == 0,
)
lam_num, V_num, p_num = 0.3, 10.0, 0.9
numeric = [float(cardinality_pmf(2, m).subs({lam: lam_num, V: V_num, p_D: p_num})) for m in range(5)]
scipy_conv = np.convolve(binom.pmf(range(3), 2, p_num), poisson.pmf(range(5), lam_num * V_num))[:5]
findings.check(
    "P(|Z| = m) agrees with scipy's binomial * Poisson convolution (n = 2, lambda V = 3, p_D = 0.9)",
    np.allclose(numeric, scipy_conv, rtol=1e-13, atol=0),
)
findings.record("cardinality_pmf_n2_lamV3_pD09", numeric)
# negative control: the same set integral without its 1/m! (n = 2 targets, m <= 4 returns, lambda V = 3, p_D = 0.9):
# already above 1 when truncated, so the check "equals 1" rejects it
no_factorial = sum(math.factorial(m) * v for m, v in enumerate(numeric))
findings.claim("Poisson-clutter likelihood is a set density", "001 Eq. 5-7", "set integral 1",
               f"{set_integrals[3]} (n = 0..3)", "reproduced" if all(v == 1 for v in set_integrals.values())
               else "not reproduced", note="needs the 1/m! of the set integral", key="poisson_set_density",
               control=("the set integral without its 1/m! (n = 2, λV = 3, p_D = 0.9, terms m ≤ 4)",
                        f"at least {no_factorial:.3g}", abs(no_factorial - 1) < 1e-12))

# %% [markdown]
# ## 5. Fixed number of targets: FISST weight = Reid's weight (document 001 Eq. 18 vs Eq. 30)
#
# The FISST child weight is $p(\sigma \mid n)\, l_{q\sigma}$ with $l_{q\sigma} = \frac{k!}{V^k}\prod_i \int
# p(z|x)p^{-}(x)dx$ (Eq. 18–19); Reid's is $p_D^{m-k}(1-p_D)^{n-(m-k)}\lambda^k \prod_i \int p(z|x)p^-(x)dx$
# (Eq. 30). Their ratio is $e^{-\lambda V}$ for *every* association $\sigma$, so the normalised
# weights coincide. Sympy checks the ratio for all associations of $n = 3$ targets and $m = 3$ returns,
# with the predictive likelihoods as free symbols.

# %%
def fisst_weight(n, m, event, predictive):
    k = sum(1 for j in event if j < 0)
    l_q_sigma = sp.factorial(k) / V**k * sp.Mul(*[predictive[i, j] for i, j in enumerate(event) if j >= 0])
    return eq6_association_prior(n, m, k, p_D) * l_q_sigma


def reid_weight(n, m, event, predictive):
    k = sum(1 for j in event if j < 0)
    return (p_D ** (m - k) * (1 - p_D) ** (n - (m - k)) * lam**k
            * sp.Mul(*[predictive[i, j] for i, j in enumerate(event) if j >= 0]))


predictive = {(i, j): sp.Symbol(f"ell_{i}{j}", positive=True) for i in range(3) for j in range(3)}
ratios = {sp.simplify(fisst_weight(3, 3, e, predictive) / reid_weight(3, 3, e, predictive))
          for e in association_events(3, 3)}
findings.check(
    "FISST (Eq. 18) / Reid (Eq. 30) weight ratio is the same constant e^(-lambda V) for all 34 children",
    ratios == {sp.exp(-lam * V)},
    ratios=[str(r) for r in ratios],
)
# negative control: Reid's weight without its false-alarm factor lambda^k: the ratio then varies between children
broken_ratios = {sp.simplify(fisst_weight(3, 3, e, predictive) / (reid_weight(3, 3, e, predictive)
                                                                   / lam ** sum(1 for j in e if j < 0)))
                 for e in association_events(3, 3)}
findings.claim("FISST weight = Reid's weight for a fixed number of targets", "001 Eq. 18 vs 30",
               "identical after normalisation", f"ratio {', '.join(map(str, ratios))} for every child",
               "reproduced" if len(ratios) == 1 else "not reproduced", key="fisst_reid_weights",
               control=("Reid's weight without its false-alarm factor λ^k", f"{len(broken_ratios)} distinct ratios",
                        len(broken_ratios) == 1))

# %%
findings.write()
