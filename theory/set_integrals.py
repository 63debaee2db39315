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
# # Set integrals, set derivatives and units (document 002, Vo–Singh–Doucet)
#
# FISST integrates a function of finite sets by the *set integral*
#
# $$\int_S f(X)\,\delta X = \sum_{n \ge 0} \frac{1}{n!}\int_{S^n} f(\{x_1,\ldots,x_n\})\,dx_1\cdots dx_n \qquad \text{(document 002, Eq. 4)}$$
#
# and differentiates a belief-mass function $\beta(S) = P(X \subseteq S)$ by the *set derivative*
# $(dF)_x(S) = \lim_{\lambda(\Delta_x)\to 0} [F(S \cup \Delta_x) - F(S)]/\lambda(\Delta_x)$ (Eq. 3). Document 002 shows
# that the set derivative at $\emptyset$ is a probability density with respect to a Poisson
# reference measure, and that its value depends on the unit of volume $K$ through $K^{|X|}$
# while probabilities do not (Prop. 1, Eq. 10–11).
#
# Checked here, symbolically (1-D Gaussian intensities and spatial pdfs, all parameters symbolic):
#
# 1. the set integral of a Poisson RFS density is 1;
# 2. the set integral of a Bernoulli RFS density is 1;
# 3. measuring volume in units of $K$ multiplies the density of an $n$-point set by $K^n$ and
#    leaves every probability unchanged (Prop. 1);
# 4. the set derivatives of the Bernoulli and Poisson belief-mass functions at $\emptyset$ are
#    their densities, and integrating the density back gives the belief mass (the generalised
#    fundamental theorem of calculus, document 002 Sec. 2.2).

# %%
from itertools import combinations

import sympy as sp

from _common import Findings, formula, integrate_sum_of_products

findings = Findings("set_integrals", "document 002 (Vo, Singh, Doucet): Eq. 3-4, 7-11, Prop. 1")

lam, s, r, K, h, h2 = sp.symbols("lambda s r K h h2", positive=True)
mu, a, b = sp.symbols("mu a b", real=True)
xs = sp.symbols("x1:5", real=True)


def gauss(x):
    return sp.exp(-((x - mu) ** 2) / (2 * s**2)) / sp.sqrt(2 * sp.pi * s**2)


@formula
def poisson_rfs_density(points):
    """Poisson RFS with intensity lambda N(x; mu, s^2): f(X) = e^-lambda prod_x lambda N(x)."""
    return sp.exp(-lam) * sp.Mul(*[lam * gauss(x) for x in points])


@formula
def bernoulli_rfs_density(points):
    """Bernoulli RFS: empty with probability 1 - r, else one point with pdf N(mu, s^2)."""
    return {0: 1 - r, 1: r * gauss(points[0]) if points else 0}.get(len(points), sp.Integer(0))


def set_integral_term(density, n):
    """(1/n!) * integral of density({x_1..x_n}) over the whole line in each x_i (Eq. 4)."""
    return integrate_sum_of_products(density(xs[:n]), xs[:n]) / sp.factorial(n)


# %% [markdown]
# ## 1. Poisson RFS: the set integral is 1
#
# The $n$-point term is $\frac{1}{n!}e^{-\lambda}(\int \lambda\mathcal N)^n = e^{-\lambda}\lambda^n/n!$ — the
# Poisson cardinality distribution — and the series sums to 1. Sympy integrates the terms
# $n = 0..4$ explicitly and sums the series to infinity.

# %%
N_TERMS = 5
poisson_terms = [sp.simplify(set_integral_term(poisson_rfs_density, n)) for n in range(N_TERMS)]
findings.check(
    f"Poisson RFS: the n-point term of the set integral is e^-lambda lambda^n / n! for n < {N_TERMS}",
    all(sp.simplify(t - sp.exp(-lam) * lam**n / sp.factorial(n)) == 0 for n, t in enumerate(poisson_terms)),
    terms=[str(t) for t in poisson_terms],
)
k = sp.symbols("k", integer=True, nonnegative=True)
poisson_total = sp.simplify(sp.summation(sp.exp(-lam) * lam**k / sp.factorial(k), (k, 0, sp.oo)))
findings.check("Poisson RFS: set integral = sum_n e^-lambda lambda^n / n! = 1", poisson_total == 1)
# negative control: the Poisson RFS density without its normalising e^-lambda
unnormalised_total = sp.simplify(sp.summation(lam**k / sp.factorial(k), (k, 0, sp.oo)))
findings.claim("set integral of a Poisson RFS density", "002 Eq. 4, 14", "1", str(poisson_total),
               "reproduced" if poisson_total == 1 else "not reproduced", note="1-D Gaussian intensity, symbolic", key="poisson_set_integral",
               control=("the density without its normalising e^(-λ)", str(unnormalised_total), unnormalised_total == 1))
findings.check(
    f"Poisson RFS: the truncated set integral is the Poisson CDF at {N_TERMS - 1}",
    sp.simplify(sum(poisson_terms) - sum(sp.exp(-lam) * lam**n / sp.factorial(n) for n in range(N_TERMS))) == 0,
)

# %% [markdown]
# ## 2. Bernoulli RFS: the set integral is 1
#
# $f(\emptyset) = 1 - r$, $f(\{x\}) = r\,p(x)$, zero on larger sets: $\int f\,\delta X = (1 - r) + r = 1$.

# %%
bernoulli_terms = [sp.simplify(set_integral_term(bernoulli_rfs_density, n)) for n in range(4)]
findings.check(
    "Bernoulli RFS: set-integral terms are (1 - r, r, 0, 0) and sum to 1",
    bernoulli_terms == [1 - r, r, 0, 0] and sp.simplify(sum(bernoulli_terms)) == 1,
    terms=[str(t) for t in bernoulli_terms],
)

# %% [markdown]
# ## 3. Units: Prop. 1 and Eq. 11
#
# Let the unit of volume be $K$ base units, so that a set $\Delta$ of base volume $h$ has
# $\lambda_K(\Delta) = h/K$. The set derivative computed with $\lambda_K$ is $K^{|X|}$ times the one
# computed in base units (each differentiation divides by $h/K$ instead of $h$); the set integral
# with $\lambda_K$ divides by $K$ once per point. Hence the density of an $n$-point set scales by
# $K^n$ and every probability $P(|X| = n, X \subseteq [a, b]) = \frac{1}{n!}\int_{[a,b]^n} f\,d\lambda^n$ is
# the same in every unit. Checked for the Poisson RFS, $n = 0..2$, with $a, b, K$ symbolic; the
# set derivatives are taken by the limit definition, not written down.

# %%
def poisson_belief_mass(S_mass):
    """beta(S) = P(X subset of S) = exp(-lambda + lambda * int_S N) for a Poisson RFS."""
    return sp.exp(-lam + lam * S_mass)


def Phi(t):
    """Gaussian CDF of N(mu, s^2)."""
    return (1 + sp.erf((t - mu) / (sp.sqrt(2) * s))) / 2


def set_derivative_at_empty(belief_of_mass, points, unit):
    """(d_K beta)_X(emptyset) by the limit definition, with Delta_i = [x_i, x_i + h_i] of volume h_i / K."""
    widths = (h, h2)[: len(points)]
    increments = [Phi(x + w) - Phi(x) for x, w in zip(points, widths)]

    def beta_with(chosen):
        return belief_of_mass(sum((increments[i] for i in chosen), sp.Integer(0)))

    # Inclusion-exclusion over which Delta_i are added: the n-fold difference quotient.
    diff = sum((-1) ** (len(points) - len(c)) * beta_with(c)
               for q in range(len(points) + 1) for c in combinations(range(len(points)), q))
    quotient = diff / sp.Mul(*[w / unit for w in widths])
    for w in widths:
        quotient = sp.limit(quotient, w, 0)
    return sp.simplify(quotient)


unit_derivatives = {n: set_derivative_at_empty(poisson_belief_mass, xs[:n], K) for n in range(3)}
findings.check(
    "Poisson RFS: (d_K beta)_X(emptyset) = K^|X| f(X) for |X| = 0, 1, 2 (limit definition, symbolic K)",
    all(sp.simplify(d - K**n * poisson_rfs_density(xs[:n])) == 0 for n, d in unit_derivatives.items()),
    derivatives={n: str(d) for n, d in unit_derivatives.items()},
)


def probability_in_interval(densities, n, unit):
    """(1/n!) int_[a,b]^n density dlambda_K^n with lambda_K(dx) = dx / K (Eq. 4 in unit K)."""
    value = integrate_sum_of_products(densities[n] / unit**n, xs[:n], a, b)
    return sp.simplify(value / sp.factorial(n))


# The derivatives just verified equal K^n f(X); integrate that closed form (Sympy cannot integrate
# the expanded exponentials it returns from the limits over a finite interval).
unit_densities = {n: K**n * poisson_rfs_density(xs[:n]) for n in unit_derivatives}
probabilities = {n: probability_in_interval(unit_densities, n, K) for n in unit_densities}
findings.check(
    "Prop. 1: P(|X| = n, X in [a, b]) from the unit-K set derivative and lambda_K does not depend on K (n = 0..2)",
    all(sp.simplify(sp.diff(p, K)) == 0 for p in probabilities.values()),
)
findings.check(
    "... and equals e^-lambda (lambda (Phi(b) - Phi(a)))^n / n! (n = 0..2)",
    all(sp.simplify(p - sp.exp(-lam) * (lam * (Phi(b) - Phi(a))) ** n / sp.factorial(n)) == 0
        for n, p in probabilities.items()),
)
findings.record("unit_scaling", "density of an n-point set in unit K = K^n x density in base units")
# negative control: the density left in base units (no K^|X|) under the unit-K measure: P then depends on K
unscaled = {n: poisson_rfs_density(xs[:n]) for n in unit_derivatives}
unscaled_depends = [n for n in unscaled if sp.simplify(sp.diff(probability_in_interval(unscaled, n, K), K)) != 0]
findings.claim("unit dependence of the density, K^|X|", "002 Prop. 1, Eq. 10-11",
               "density x K^|X|, probabilities unchanged", "K^|X| f(X); dP/dK = 0 (n = 0..2)", "reproduced",
               note="set derivatives by the limit definition, symbolic K", key="unit_dependence",
               control=("the density not rescaled by K^|X|", f"dP/dK ≠ 0 for n = {', '.join(map(str, unscaled_depends))}",
                        not unscaled_depends))

# %% [markdown]
# ## 4. The set derivative recovers the density (generalised fundamental theorem)
#
# For a Bernoulli RFS, $\beta(S) = 1 - r + r\int_S p(x)\,dx$. Its set derivatives at $\emptyset$ are
# $\beta(\emptyset) = 1 - r = f(\emptyset)$, $(d\beta)_x(\emptyset) = r\,p(x) = f(\{x\})$ and
# $(d\beta)_{\{x_1,x_2\}}(\emptyset) = 0 = f(\{x_1,x_2\})$ (unit $K = 1$); and the set integral of
# that density over $S = [a, b]$ gives back $\beta(S)$.

# %%
def bernoulli_belief_mass(S_mass):
    return 1 - r + r * S_mass


bernoulli_derivatives = {n: set_derivative_at_empty(bernoulli_belief_mass, xs[:n], 1) for n in range(3)}
findings.check(
    "Bernoulli RFS: set derivatives of the belief mass at the empty set are (1 - r, r p(x1), 0) = f",
    all(sp.simplify(d - bernoulli_rfs_density(xs[:n])) == 0 for n, d in bernoulli_derivatives.items()),
    derivatives={n: str(d) for n, d in bernoulli_derivatives.items()},
)
reintegrated = bernoulli_rfs_density(()) + integrate_sum_of_products(bernoulli_rfs_density(xs[:1]), xs[:1], a, b)
findings.check(
    "fundamental theorem: int_[a,b] f delta X = beta([a, b]) = 1 - r + r (Phi(b) - Phi(a))",
    sp.simplify(reintegrated - bernoulli_belief_mass(Phi(b) - Phi(a))) == 0,
)
# negative control: a Bernoulli density missing its existence probability r on the one-point term
broken_bernoulli = {0: 1 - r, 1: gauss(xs[0]), 2: sp.Integer(0)}
broken_equal = all(sp.simplify(d - broken_bernoulli[n]) == 0 for n, d in bernoulli_derivatives.items())
findings.claim("set derivative of the belief mass is the density", "002 Sec. 2.2, Prop. 1",
               "f(X) = (d beta)_X(emptyset)", "Bernoulli and Poisson RFS, |X| <= 2", "reproduced",
               note="and the set integral of f over S gives back beta(S)", key="set_derivative",
               control=("a Bernoulli density without r on its one-point term", "differs from the set derivative at |X| = 1"
                        if not broken_equal else "equals the set derivative", broken_equal))
base_unit_densities = {n: poisson_rfs_density(xs[:n]) for n in range(4)}
poisson_reintegrated = sum(probability_in_interval(base_unit_densities, n, 1) for n in range(4))
q = sp.Symbol("q")
findings.check(
    "fundamental theorem, Poisson RFS: the set-integral terms n = 0..3 over [a, b] are the Taylor terms of "
    "beta([a, b]) = exp(-lambda + lambda (Phi(b) - Phi(a)))",
    sp.simplify(sp.series(poisson_belief_mass(q), q, 0, 4).removeO().subs(q, Phi(b) - Phi(a))
                - poisson_reintegrated) == 0,
)

# %%
findings.write()
