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
# # How many children does a hypothesis have? (document 000, Eq. 4)
#
# Faber, Chakravorty & Hussein (document 000, Sec. II-A) state that a parent hypothesis with
# $M$ objects, given a scan of $m$ returns, splits into
#
# $$A(M, m) = \sum_{n=0}^{\min(M, m)} \binom{M}{n}\binom{m}{n}\, n! \qquad \text{(Eq. 4)}$$
#
# children: choose the $n$ detected objects, the $n$ returns they produced, and match them
# ($n!$ ways); every other return is clutter. With at most one birth (in one of $M_b$ regions)
# or one death (of one of $M_d$ objects) per scan (Sec. II-C) a parent has
# $A(M,m) + M_b A(M{+}1,m) + M_d A(M{-}1,m)$ children.
#
# This notebook checks, in exact integer arithmetic:
#
# 1. Eq. 4 against a brute-force enumeration of association events for all $M, m \le 6$, and
#    the library's `hypotrack.association.count_associations` against both;
# 2. closed forms: $A(M,m) = M!\,L_M^{(m-M)}(-1)$ (generalised Laguerre polynomial),
#    $A(M,m) = {}_2F_0(-M,-m;;1)$, the recurrence $A(M,m) = A(M{-}1,m) + m\,A(M{-}1,m{-}1)$
#    (proved symbolically term by term) and the exponential generating function
#    $\sum_M A(M,m)\,x^M/M! = e^x (1+x)^m$;
# 3. the published value $A(10, 5) = 63{,}591$;
# 4. the birth/death child count against enumeration, and `count_children`;
# 5. the growth of $A(n,n)$ up to $n = 70$ against Perron's Laguerre asymptotics,
#    $A(n,n) \sim n!\, e^{2\sqrt n - 1/2} / (2\sqrt\pi\, n^{1/4})$.
#
# Run as a script: `python theory/hypothesis_count.py` (exit status 0 iff every check holds).

# %%
import math
from math import comb, factorial

import matplotlib.pyplot as plt
import sympy as sp

from _common import Findings, association_events, formula
from hypotrack.association import count_associations, count_children

findings = Findings("hypothesis_count", "document 000 (Faber, Chakravorty, Hussein): Eq. 4 and Sec. II-C")


@formula
def eq4_count(M: int, m: int) -> int:
    """Document 000 Eq. 4, as printed."""
    return sum(comb(M, n) * comb(m, n) * factorial(n) for n in range(min(M, m) + 1))


@formula
def child_count(M: int, m: int, n_birth_regions: int, n_deaths: int) -> int:
    """Document 000 Sec. II-C: no event, one birth in one of M_b regions, or one death of M_d objects."""
    total = eq4_count(M, m) + n_birth_regions * eq4_count(M + 1, m)
    return total + (n_deaths * eq4_count(M - 1, m) if M >= 1 else 0)


# %% [markdown]
# ## 1. Eq. 4 against brute-force enumeration
#
# The oracle enumerates every map *returns → objects ∪ {clutter}* and keeps those in which no
# object receives two returns. It knows nothing of binomial coefficients.

# %%
brute = {}
for M in range(7):
    for m in range(7):
        events = list(association_events(M, m))
        assert len(set(events)) == len(events)
        brute[M, m] = len(events)

mismatch = [(M, m) for (M, m), v in brute.items() if v != eq4_count(M, m)]
findings.check("Eq. 4 equals brute-force enumeration for all M, m <= 6", not mismatch, mismatches=mismatch)
lib_mismatch = [(M, m) for (M, m), v in brute.items() if count_associations(M, m) != v]
findings.check(
    "hypotrack count_associations equals brute-force enumeration for all M, m <= 6",
    not lib_mismatch,
    mismatches=lib_mismatch,
)
findings.record("brute_force_table_M_rows_m_columns", [[brute[M, m] for m in range(7)] for M in range(7)])
print("A(M, m), M = rows 0..6, m = columns 0..6")
for M in range(7):
    print(" ".join(f"{brute[M, m]:7d}" for m in range(7)))

# %% [markdown]
# ## 2. The published value A(10, 5) = 63,591
#
# The sum has six terms: $1 + 50 + 900 + 7200 + 25200 + 30240$.

# %%
PUBLISHED_A_10_5 = 63591
terms_10_5 = [comb(10, n) * comb(5, n) * factorial(n) for n in range(6)]
findings.check("A(10, 5) = 63,591 (document 000 text)", eq4_count(10, 5) == PUBLISHED_A_10_5, value=eq4_count(10, 5))
findings.check("count_associations(10, 5) = 63,591", count_associations(10, 5) == PUBLISHED_A_10_5)
findings.record("A_10_5", eq4_count(10, 5))
# negative control: the count without its false-alarm terms (every return on an object: only n = min(M, m))
no_false_alarms_10_5 = comb(10, 5) * factorial(5)
findings.claim("A(10, 5) associations", "000 Sec. II-A, Eq. 4", f"{PUBLISHED_A_10_5:,}", f"{eq4_count(10, 5):,}",
               "reproduced" if eq4_count(10, 5) == PUBLISHED_A_10_5 else "not reproduced",
               note="exact integer; also by brute-force enumeration for all M, m <= 6", key="count_example", evidence="brute force",
               control=("the count without false alarms (every return on an object, C(10, 5) 5!)",
                        f"{no_false_alarms_10_5:,}", no_false_alarms_10_5 == PUBLISHED_A_10_5))
findings.record("A_10_5_terms", terms_10_5)
print("terms of A(10, 5):", terms_10_5)

# %% [markdown]
# ## 3. Closed forms
#
# **Laguerre.** With $L_n^{(\alpha)}(x) = \sum_k (-1)^k \binom{n+\alpha}{n-k} x^k/k!$,
# $M!\,L_M^{(m-M)}(-1) = \sum_k \frac{M!}{k!}\binom{m}{M-k}$, and putting $j = M - k$ gives Eq. 4.
# Sympy's own `assoc_laguerre` is evaluated and compared exactly for all $M, m \le 30$
# (961 pairs, including the negative-$\alpha$ half $m < M$).
#
# **Recurrence.** Object $M$ is either undetected ($A(M{-}1,m)$ ways) or takes one of the $m$
# returns ($m\,A(M{-}1,m{-}1)$ ways). Term by term this is Pascal's rule, which Sympy proves for
# symbolic $M, m, n$; boundary values $A(0,m) = A(M,0) = 1$ close the induction.
#
# **Hypergeometric.** $(-M)_n(-m)_n/n! = \binom{M}{n}\binom{m}{n} n!$, so $A = {}_2F_0(-M,-m;;1)$;
# `hyperexpand` is slow, so it is checked for $M, m \le 6$.
#
# **Generating function.** $e^x(1+x)^m = \sum_M x^M \sum_j \binom{m}{j}/(M-j)!$, i.e. the
# binomial convolution of the all-ones sequence with the falling factorials of $m$.

# %%
N_CLOSED = 30
laguerre_bad = [
    (M, m)
    for M in range(N_CLOSED + 1)
    for m in range(N_CLOSED + 1)
    if sp.factorial(M) * sp.assoc_laguerre(M, m - M, -1) != eq4_count(M, m)
]
findings.check(
    f"A(M, m) = M! L_M^(m-M)(-1) exactly for all M, m <= {N_CLOSED}", not laguerre_bad, mismatches=laguerre_bad
)

Ms, ms, ns = sp.symbols("M m n", integer=True, nonnegative=True)


def _term(M, m, n):
    return sp.binomial(M, n) * sp.binomial(m, n) * sp.factorial(n)


pascal_residual = sp.simplify(sp.combsimp(_term(Ms, ms, ns) - _term(Ms - 1, ms, ns) - ms * _term(Ms - 1, ms - 1, ns - 1)))
findings.check(
    "recurrence A(M,m) = A(M-1,m) + m A(M-1,m-1) holds term by term (symbolic proof)",
    pascal_residual == 0,
    residual=str(pascal_residual),
)
recurrence_bad = [
    (M, m)
    for M in range(1, N_CLOSED + 1)
    for m in range(1, N_CLOSED + 1)
    if eq4_count(M, m) != eq4_count(M - 1, m) + m * eq4_count(M - 1, m - 1)
]
boundary_ok = all(eq4_count(0, k) == 1 and eq4_count(k, 0) == 1 for k in range(N_CLOSED + 1))
findings.check(
    f"recurrence and boundary A(0,m) = A(M,0) = 1 hold exactly for M, m <= {N_CLOSED}",
    not recurrence_bad and boundary_ok,
)
findings.check(
    f"symmetry A(M, m) = A(m, M) for M, m <= {N_CLOSED}",
    all(eq4_count(M, m) == eq4_count(m, M) for M in range(N_CLOSED + 1) for m in range(M)),
)

hyper_bad = [
    (M, m)
    for M in range(7)
    for m in range(7)
    if sp.hyperexpand(sp.hyper([-M, -m], [], 1)) != eq4_count(M, m)
]
findings.check("A(M, m) = 2F0(-M, -m;; 1) for all M, m <= 6", not hyper_bad, mismatches=hyper_bad)

x = sp.symbols("x")
egf_bad = []
for m in range(7):
    series = sp.series(sp.exp(x) * (1 + x) ** m, x, 0, N_CLOSED + 1).removeO()
    egf_bad += [(M, m) for M in range(N_CLOSED + 1) if sp.factorial(M) * series.coeff(x, M) != eq4_count(M, m)]
findings.check(
    f"EGF: M! [x^M] e^x (1+x)^m = A(M, m) for m <= 6, M <= {N_CLOSED}", not egf_bad, mismatches=egf_bad
)
lib_closed_bad = [
    (M, m) for M in range(N_CLOSED + 1) for m in range(N_CLOSED + 1) if count_associations(M, m) != eq4_count(M, m)
]
findings.check(f"count_associations equals Eq. 4 for all M, m <= {N_CLOSED}", not lib_closed_bad)
findings.record("closed_form", "A(M, m) = M! * L_M^(m-M)(-1) = 2F0(-M, -m;; 1); EGF e^x (1+x)^m")

# %% [markdown]
# ## 4. Children with single birth/death events (Sec. II-C)
#
# The oracle builds each child explicitly: a population event (none; a newborn labelled by its
# birth region; or the death of one of the first $M_d$ objects), the resulting set of object
# labels, and an injective association of the returns to those labels or clutter. Children are
# collected in a set, so two different events that led to the same child would be counted once.

# %%
def enumerate_children(M, m, n_birth_regions, n_deaths):
    objects = tuple(range(M))
    populations = [objects]
    populations += [objects + (("birth", r),) for r in range(n_birth_regions)]
    populations += [tuple(o for o in objects if o != d) for d in range(n_deaths)]
    children = set()
    for labels in populations:
        for event in association_events(len(labels), m):
            children.add((frozenset(labels), tuple(labels[j] if j >= 0 else None for j in event)))
    return children


child_rows = []
for M in range(5):
    for m in range(5):
        for n_birth_regions in range(3):
            for n_deaths in range(M + 1):
                n_enum = len(enumerate_children(M, m, n_birth_regions, n_deaths))
                child_rows.append(
                    (M, m, n_birth_regions, n_deaths, n_enum, child_count(M, m, n_birth_regions, n_deaths),
                     count_children(M, m, n_birth_regions, n_deaths))
                )
bad = [r for r in child_rows if not (r[4] == r[5] == r[6])]
findings.check(
    "child count A(M,m) + M_b A(M+1,m) + M_d A(M-1,m) equals enumeration and count_children "
    "(M, m <= 4, M_b <= 2, M_d <= M)",
    not bad,
    mismatches=bad,
)
findings.record("children_example_M10_m5_Mb10_Md10", child_count(10, 5, 10, 10))
# negative control: the same count without its birth term M_b A(M+1, m), against the same enumeration
no_birth_equal = sum(1 for (M, m, n_b, n_d, n_enum, _, _) in child_rows if eq4_count(M, m) + n_d * eq4_count(M - 1, m)
                     == n_enum) if child_rows else 0
findings.claim("children with single birth/death events", "000 Sec. II-C",
               "A(M,m) + M_b A(M+1,m) + M_d A(M-1,m)", f"equal to enumeration in {len(child_rows)} cases",
               "reproduced" if not bad else "not reproduced",
               note="M, m <= 4, M_b <= 2, M_d <= M; e.g. 1,485,011 children for M=10, m=5, M_b=M_d=10", key="child_count", evidence="brute force",
               control=("the count without its birth term M_b A(M+1, m)",
                        f"equal to enumeration in {no_birth_equal} of {len(child_rows)} cases",
                        no_birth_equal == len(child_rows)))
print("children of a 10-object parent, 5 returns, 10 birth regions, 10 mortal objects:", child_count(10, 5, 10, 10))

# %% [markdown]
# ## 5. Growth of A(n, n)
#
# $A(n,n) = n!\,L_n(-1)$ and Perron's formula for Laguerre polynomials off the positive axis,
# $L_n(-1) = \frac{e^{-1/2} e^{2\sqrt n}}{2\sqrt\pi\, n^{1/4}}\,(1 + O(n^{-1/2}))$, give
#
# $$\ln A(n,n) = \ln n! + 2\sqrt n - \tfrac12 - \tfrac14\ln n - \ln(2\sqrt\pi) + O(n^{-1/2}).$$
#
# So the count is $n!$ (all returns assigned) times a sub-exponential factor $e^{2\sqrt n}$.
# The table is exact to $n = 70$; the checks confirm the ratio to the asymptote tends to 1 at
# the $n^{-1/2}$ rate (i.e. $\sqrt n\,(\text{ratio} - 1)$ settles to a constant).

# %%
N_GROWTH = 70
LOG10 = math.log(10)


def perron_log(n: int) -> float:
    return math.lgamma(n + 1) + 2 * math.sqrt(n) - 0.5 - 0.25 * math.log(n) - math.log(2 * math.sqrt(math.pi))


growth = []
for n in range(1, N_GROWTH + 1):
    a = eq4_count(n, n)
    ln_a = math.log(a)
    ratio = math.exp(ln_a - perron_log(n))
    growth.append(
        {
            "n": n,
            "A_exact": a,
            "digits": len(str(a)),
            "log10_A": ln_a / LOG10,
            "log10_n_factorial": math.lgamma(n + 1) / LOG10,
            "log10_perron": perron_log(n) / LOG10,
            "ratio_to_perron": ratio,
            "sqrt_n_times_rel_error": math.sqrt(n) * (ratio - 1),
        }
    )

rel_err = [row["ratio_to_perron"] - 1 for row in growth]
scaled = [row["sqrt_n_times_rel_error"] for row in growth if row["n"] >= 40]
findings.check(
    "ratio A(n,n) / Perron asymptote decreases monotonically to 1 for n = 2..70",
    all(0 < b < a for a, b in zip(rel_err[1:], rel_err[2:])),
    ratio_at_70=growth[-1]["ratio_to_perron"],
)
findings.check(
    "sqrt(n) * (ratio - 1) varies by < 1 % over n = 40..70 (O(n^-1/2) convergence)",
    (max(scaled) - min(scaled)) < 0.01 * max(scaled),
    spread=(min(scaled), max(scaled)),
)
first_over = {
    threshold: next(r["n"] for r in growth if r["log10_A"] >= threshold) for threshold in (8, 33, 100)
}
findings.record("growth_table", growth)
findings.claim("growth of A(n, n)", "000 Eq. 4 (extension)", "--",
               f"n! e^(2 sqrt n - 1/2) / (2 sqrt(pi) n^(1/4)) (ratio {growth[-1]['ratio_to_perron']:.4f} at n = 70)",
               "extension", note=f"A(n,n) first exceeds 1e8 at n = {first_over[8]}, 1e33 at n = {first_over[33]}, "
                                 f"1e100 at n = {first_over[100]}; closed form n! L_n(-1)", key="count_growth")
findings.record("first_n_with_A_nn_at_least_1e8_1e33_1e100", first_over)
print(" n  digits  log10 A(n,n)  log10 n!  ratio to Perron")
for row in growth:
    if row["n"] in (1, 2, 5, 10, 20, 30, 40, 50, 60, 70):
        print(
            f"{row['n']:2d}  {row['digits']:6d}  {row['log10_A']:12.4f}  {row['log10_n_factorial']:8.4f}"
            f"  {row['ratio_to_perron']:.6f}"
        )
print("first n with A(n, n) >= 1e8, 1e33, 1e100:", first_over)

# %%
fig, (ax, ax2) = plt.subplots(1, 2, figsize=(6.5, 4.3))  # the report's line width: 8 pt text prints at 8 pt
n_axis = [r["n"] for r in growth]
ax.semilogy(n_axis, [10 ** r["log10_A"] for r in growth], "k-", lw=2, label="A(n, n), Eq. 4 (exact)")
ax.semilogy(n_axis, [10 ** r["log10_perron"] for r in growth], "C1--", label=r"$n!\,e^{2\sqrt{n}-1/2}/(2\sqrt{\pi}n^{1/4})$")
ax.semilogy(n_axis, [10 ** r["log10_n_factorial"] for r in growth], "C0:", label="n! (all returns assigned)")
for threshold, style, what in ((8, "C3", "exhaustive HOMHT limit"), (33, "C2", "R-FISST reach")):
    sup = str(threshold).translate(str.maketrans("0123456789", "⁰¹²³⁴⁵⁶⁷⁸⁹"))
    ax.axhline(10.0**threshold, color=style, lw=0.8, label=f"10{sup}: {what} (doc. 000 Fig 15)")
ax.set_ylim(bottom=0.5)
ax.set_xlabel("objects = returns, n", fontsize=9)
ax.set_ylabel("children A(n, n) (count)", fontsize=9)
ax.set_title("Children per hypothesis,\ndocument 000 Eq. 4", fontsize=9)
fig.legend(*ax.get_legend_handles_labels(), loc="lower center", ncol=2, fontsize=7, frameon=False)
ax2.plot(n_axis, [r["ratio_to_perron"] for r in growth], "k.-")
ax2.axhline(1.0, color="grey", lw=0.8)
ax2.set_xlabel("n", fontsize=9)
ax2.set_ylabel("A(n, n) / asymptote (dimensionless)", fontsize=9)
ax2.set_title(r"Perron asymptote: ratio $\to 1$" "\n" r"as $O(n^{-1/2})$", fontsize=9)
fig.tight_layout(rect=(0, 0.14, 1, 1))  # the legend below both panels, clear of the curves
findings.figure(fig, "growth")
plt.show()

# %%
findings.write()
