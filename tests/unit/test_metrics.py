"""OSPA and GOSPA: published vectors and brute-force permutation oracles."""

import itertools
import math

import numpy as np
import pytest

from hypotrack.metrics import gospa, ospa, ospa_series

TRACKS_1D = [0.5, 1.5, 2.5, 3.5]
TRUTHS_1D = [0, 1, 2, 3, 4]


def pairwise(X, Y):
    X, Y = (np.asarray(S, float) for S in (X, Y))
    X, Y = (S[:, None] if S.ndim == 1 else S for S in (X, Y))
    return np.array([[np.linalg.norm(x - y) for y in Y] for x in X]).reshape(len(X), len(Y))


def brute_ospa(X, Y, c, p):
    """Definition (Schuhmacher et al. 2008, Eq. 3) by exhaustive permutation search."""
    D = np.minimum(pairwise(X, Y), c)
    if D.shape[0] > D.shape[1]:
        D = D.T
    m, n = D.shape
    if n == 0:
        return 0.0
    if math.isinf(p):
        if m != n:
            return c
        return min(max(D[i, pi] for i, pi in enumerate(perm)) for perm in itertools.permutations(range(n)))
    perms = itertools.permutations(range(n), m)
    best = min(sum(D[i, pi] ** p for i, pi in enumerate(perm)) for perm in perms)
    return ((best + c**p * (n - m)) / n) ** (1 / p)


def partial_assignments(nx, ny):
    """Every injective partial map from X's indices to Y's, as lists of pairs."""
    for k in range(min(nx, ny) + 1):
        for xs in itertools.combinations(range(nx), k):
            for ys in itertools.permutations(range(ny), k):
                yield list(zip(xs, ys))


def brute_gospa(X, Y, c, p):
    """GOSPA with α = 2 from its assignment form, on *uncut* distances, by exhaustive search.

    Returns (value, localisation, n_missed, n_false) of the optimal partial assignment.
    """
    D = pairwise(X, Y)
    nx, ny = D.shape
    best = None
    for gamma in partial_assignments(nx, ny):
        d = [D[i, j] for i, j in gamma]
        unassigned = nx + ny - 2 * len(gamma)
        if math.isinf(p):
            cost = max(d + ([c] if unassigned else []), default=0.0)
        else:
            cost = sum(x**p for x in d) + c**p / 2 * unassigned
        if best is None or cost < best[0]:
            loc = max(d, default=0.0) if math.isinf(p) else sum(x**p for x in d)
            best = (cost, loc, ny - len(gamma), nx - len(gamma))
    value = best[0] if math.isinf(p) else best[0] ** (1 / p)
    return value, best[1], best[2], best[3]


def random_set(rng, k, dim=2):
    return rng.uniform(0, 10, size=(k, dim))


def random_problems(seed, count, max_size=4, c_range=(0.5, 8)):
    """Random (X, Y, c) triples with 0..max_size points per set."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        sizes = rng.integers(0, max_size + 1, size=2)
        yield random_set(rng, int(sizes[0])), random_set(rng, int(sizes[1])), float(rng.uniform(*c_range))


# --- published vectors -----------------------------------------------------------------


@pytest.mark.parametrize("p, expected", [(1, 2.4), (2, 4.49444), (np.inf, 10.0)])
def test_published_ospa_1d(p, expected):
    assert ospa(TRACKS_1D, TRUTHS_1D, c=10, p=p) == pytest.approx(expected, abs=5e-6)


def test_published_gospa_1d():
    r = gospa(TRACKS_1D, TRUTHS_1D, c=10, p=1, alpha=2)
    assert r.value == pytest.approx(7.0)
    # Four pairs at 0.5, one missed truth at c/2 = 5, nothing false.
    assert (r.localisation, r.missed, r.false) == pytest.approx((2.0, 5.0, 0.0))
    assert (r.n_missed, r.n_false) == (1, 0)
    assert r.assignment.shape == (4, 2)


def test_published_ospa_2d():
    X = [[3.7, 6.4], [0.2, 4.9]]
    Y = [[4.3, 6.6], [8.3, 4.0]]
    assert ospa(X, Y, c=100, p=2) == pytest.approx(4.8280, abs=5e-5)


def test_assignment_on_powered_distances_not_plain_distances():
    # Σ d prefers pairing (5,1)->(2,4), (4,1)->(3,1) (5.24 < 5.61), but Σ d² prefers the
    # other pairing (17 < 19): the correct OSPA is sqrt(17/2), the min(d, c) shortcut sqrt(19/2).
    X = [[5.0, 1.0], [4.0, 1.0]]
    Y = [[2.0, 4.0], [3.0, 1.0]]
    assert ospa(X, Y, c=100, p=2) == pytest.approx(math.sqrt(17 / 2))
    assert gospa(X, Y, c=100, p=2).value == pytest.approx(math.sqrt(17))


# --- brute-force oracles -----------------------------------------------------------------


@pytest.mark.parametrize("p", [1, 2, np.inf])
def test_ospa_matches_brute_force(p):
    for X, Y, c in random_problems(10, 150):
        assert ospa(X, Y, c, p) == pytest.approx(brute_ospa(X, Y, c, p), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("p", [1, 2, np.inf])
def test_gospa_matches_brute_force_with_parts(p):
    for X, Y, c in random_problems(11, 150):
        r = gospa(X, Y, c, p)
        value, loc, n_missed, n_false = brute_gospa(X, Y, c, p)
        assert r.value == pytest.approx(value, rel=1e-12, abs=1e-12)
        if math.isinf(p):
            assert r.value == max(r.localisation, r.missed, r.false)
            continue
        assert r.localisation == pytest.approx(loc, rel=1e-12, abs=1e-12)
        assert (r.n_missed, r.n_false) == (n_missed, n_false)
        # The decomposition adds up to value**p.
        assert r.localisation + r.missed + r.false == pytest.approx(r.value**p, rel=1e-12)
        assert r.missed == pytest.approx(c**p / 2 * n_missed)
        # The reported pairs are real, distinct and within the cut-off.
        D = pairwise(X, Y)
        if r.assignment.size:
            assert np.all(D[r.assignment[:, 0], r.assignment[:, 1]] < c)
        assert len(set(r.assignment[:, 0])) == len(r.assignment) == len(set(r.assignment[:, 1]))


def test_gospa_general_alpha_definition():
    # For |X| <= |Y|: GOSPA^p = min_π Σ min(d, c)^p + c^p/α (|Y| − |X|)  (Rahmathullah et al., Def. 1).
    rng = np.random.default_rng(12)
    for X, Y, c in random_problems(12, 60, max_size=3, c_range=(1, 6)):
        p, alpha = 2.0, float(rng.uniform(0.2, 2))
        small, large = (X, Y) if len(X) <= len(Y) else (Y, X)
        D = np.minimum(pairwise(small, large), c)
        perms = itertools.permutations(range(len(large)), len(small))
        best = min((sum(D[i, j] ** p for i, j in enumerate(perm)) for perm in perms), default=0.0)
        expected = (best + c**p / alpha * (len(large) - len(small))) ** (1 / p)
        r = gospa(X, Y, c, p, alpha=alpha)
        assert r.value == pytest.approx(expected, rel=1e-12, abs=1e-12)
        assert r.localisation + r.missed + r.false == pytest.approx(r.value**p, rel=1e-12, abs=1e-12)


# --- special cases -----------------------------------------------------------------------


def test_empty_sets():
    assert ospa([], [], c=3, p=2) == 0.0
    assert ospa(np.zeros((0, 2)), [[1.0, 2.0]], c=3, p=2) == 3.0
    assert ospa([[1.0, 2.0]], [], c=3, p=np.inf) == 3.0
    r = gospa([], [[1.0, 2.0], [3.0, 4.0]], c=3, p=2)
    assert (r.value, r.missed, r.false, r.n_missed) == (pytest.approx(3.0), 9.0, 0.0, 2)
    assert r.assignment.shape == (0, 2)
    assert gospa([], [], c=3, p=1).value == 0.0


def test_pair_beyond_cutoff_is_missed_plus_false():
    r = gospa([[0.0, 0.0]], [[10.0, 0.0]], c=2, p=1)
    assert (r.n_missed, r.n_false, r.localisation) == (1, 1, 0.0)
    assert r.value == pytest.approx(2.0)


def test_ospa_series():
    rng = np.random.default_rng(13)
    Xs = [random_set(rng, k) for k in (0, 2, 3, 1)]
    Ys = [random_set(rng, k) for k in (0, 3, 3, 0)]
    series = ospa_series(Xs, Ys, c=5, p=2)
    np.testing.assert_allclose(series, [ospa(X, Y, 5, 2) for X, Y in zip(Xs, Ys)])
    assert series[0] == 0.0 and series[3] == 5.0
    assert ospa_series([], [], c=1).shape == (0,)


# --- bad input ---------------------------------------------------------------------------


@pytest.mark.parametrize("fn", [ospa, gospa])
def test_bad_input(fn):
    good = [[0.0, 1.0]]
    with pytest.raises(ValueError, match="X"):
        fn([[np.nan, 1.0]], good, 1.0, 2)
    with pytest.raises(ValueError, match="Y"):
        fn(good, np.ones((2, 2, 2)), 1.0, 2)
    with pytest.raises(ValueError, match="dimension"):
        fn(good, [[0.0, 1.0, 2.0]], 1.0, 2)
    for c in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="c"):
            fn(good, good, c, 2)
    for p in (0.5, -1, np.nan):
        with pytest.raises(ValueError, match="p"):
            fn(good, good, 1.0, p)
    with pytest.raises(TypeError, match="p"):
        fn(good, good, 1.0, "2")


def test_bad_alpha_and_series_lengths():
    for alpha in (0.0, 2.5, np.nan):
        with pytest.raises(ValueError, match="alpha"):
            gospa([[0.0]], [[1.0]], 1.0, 1, alpha=alpha)
    with pytest.raises(ValueError, match="X_seq"):
        ospa_series([[[0.0]]], [], c=1)
    with pytest.raises(ValueError, match="c"):
        ospa_series([], [], c=0)


def test_default_order_is_one_by_hand():
    """Defaults p = 1 (OSPA, GOSPA) and α = 2 (GOSPA): X = {(0,0), (10,0)}, Y = {(1,0)}, c = 5.
    OSPA: (1 + 5·1) / 2 = 3 (p = 2 would give √13). GOSPA: 1 + 5/2 = 3.5 (X's unassigned
    point is a false estimate, c^p/α)."""
    X = np.array([[0.0, 0.0], [10.0, 0.0]])
    Y = np.array([[1.0, 0.0]])
    assert ospa(X, Y, 5.0) == pytest.approx(3.0, abs=1e-12)
    np.testing.assert_allclose(ospa_series([X, Y], [Y, X], 5.0), [3.0, 3.0], atol=1e-12)
    r = gospa(X, Y, 5.0)
    assert r.value == pytest.approx(3.5, abs=1e-12)
    assert (r.localisation, r.missed, r.false) == pytest.approx((1.0, 0.0, 2.5), abs=1e-12)
    np.testing.assert_array_equal(r.assignment, [[0, 0]])


@pytest.mark.parametrize("call, exc, message", [
    (lambda: gospa(np.zeros((1, 2)), np.zeros((1, 2)), 0.0), ValueError, "c must be a finite number > 0, got 0.0"),
    (lambda: ospa_series([np.zeros((1, 2))], [np.zeros((1, 2))], -1.0), ValueError,
     "c must be a finite number > 0, got -1.0"),
    (lambda: gospa(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, alpha=True), TypeError,
     "alpha must be a real number in (0, 2], got bool"),
    (lambda: gospa(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, alpha="2"), TypeError,
     "alpha must be a real number in (0, 2], got str"),
    (lambda: ospa(np.zeros((1, 2)), np.full((1, 2), np.nan), 1.0), ValueError, "Y must be finite (no NaN or inf)"),
    (lambda: ospa(np.zeros((2, 2, 2)), np.zeros((1, 2)), 1.0), ValueError,
     "X must be an (n, d) array of points, got shape (2, 2, 2)"),
    (lambda: ospa(np.zeros((1, 2)), np.zeros((2, 2, 2)), 1.0), ValueError,
     "Y must be an (n, d) array of points, got shape (2, 2, 2)"),
    (lambda: ospa(np.zeros((1, 2)), np.zeros((1, 2)), 1.0, p="2"), TypeError,
     "p must be a real number >= 1 or inf, got str"),
])
def test_metric_messages(call, exc, message):
    with pytest.raises(exc) as info:
        call()
    assert str(info.value) == message


def test_p_infinity_is_the_brute_force_bottleneck():
    """p = ∞ with equal cardinalities: OSPA = min over assignments of the largest cut-off distance
    (by enumerating all permutations); the binary search over distance levels must find the
    smallest feasible level on every one of these random 4 × 4 problems."""
    rng = np.random.default_rng(11)
    for _ in range(40):
        X, Y = rng.uniform(0, 10, size=(4, 2)), rng.uniform(0, 10, size=(4, 2))
        D = np.minimum(np.linalg.norm(X[:, None] - Y[None], axis=-1), 6.0)
        want = min(max(D[i, s[i]] for i in range(4)) for s in itertools.permutations(range(4)))
        assert ospa(X, Y, 6.0, p=math.inf) == pytest.approx(want, abs=1e-12)
        assert gospa(X, Y, 6.0, p=math.inf).value == pytest.approx(want, abs=1e-12)


def test_empty_set_of_another_dimension_is_not_compared():
    """An empty set has no points to compare, so its declared dimension is irrelevant."""
    assert ospa(np.zeros((0, 3)), np.zeros((1, 2)), 2.0) == pytest.approx(2.0)
    assert ospa(np.zeros((1, 2)), np.zeros((0, 3)), 2.0) == pytest.approx(2.0)
