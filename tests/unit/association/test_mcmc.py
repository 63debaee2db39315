"""R-FISST MCMC search (hypotrack.association.samplers.chain, re-exported by
hypotrack.association.mcmc) against brute-force enumeration."""

import itertools

import numpy as np
import pytest

from hypotrack.association.mcmc import MCMC_VARIANTS, event_log_weights, mcmc_search, neighbour_completion


def brute_force_events(m, n_exclusive, n_options):
    """Every event over m returns by itertools: exclusive columns distinct, options free."""
    opts = list(range(n_exclusive)) + [-1 - t for t in range(n_options)]
    rows = [a for a in itertools.product(opts, repeat=m) if len({x for x in a if x >= 0}) == sum(x >= 0 for x in a)]
    return np.array(rows, dtype=np.int64).reshape(len(rows), m)


def naive_log_weight(score, n_obj, n_excl, phi, a):
    total, k, b = 0.0, 0, 0
    for i, c in enumerate(a):
        total += score[i, c if c >= 0 else n_excl - 1 - c]
        k += 0 <= c < n_obj
        b += n_obj <= c < n_excl
    return total + phi[k, b]


def random_problem(rng, m, n_obj, n_birth, n_options, forbid=0.2):
    n_excl = n_obj + n_birth
    score = rng.normal(scale=2.0, size=(m, n_excl + n_options))
    score[:, :n_excl][rng.random((m, n_excl)) < forbid] = -np.inf
    phi = rng.normal(size=(n_obj + 1, n_birth + 1))
    if n_birth:
        phi[:, 2:] = -np.inf  # at most one birth, as under document 000 Eq. 30
    return score, n_excl, phi


def test_gather_sum_equals_naive_sum():
    rng = np.random.default_rng(0)
    score, n_excl, phi = random_problem(rng, 4, 3, 2, 2)
    events = brute_force_events(4, n_excl, 2)
    fast = event_log_weights(score, 3, n_excl, phi, events)
    slow = np.array([naive_log_weight(score, 3, n_excl, phi, a) for a in events])
    np.testing.assert_array_equal(np.isfinite(fast), np.isfinite(slow))
    fin = np.isfinite(slow)
    np.testing.assert_allclose(fast[fin], slow[fin], rtol=0, atol=1e-12)


@pytest.mark.parametrize("variant", MCMC_VARIANTS)
def test_visited_events_are_distinct_feasible_and_exactly_weighted(variant):
    rng = np.random.default_rng(1)
    for trial in range(5):
        m, n_obj, n_birth, n_opt = 4, 3, 2, 1 + trial % 2
        score, n_excl, phi = random_problem(rng, m, n_obj, n_birth, n_opt)
        events, lw = mcmc_search(score, n_obj, n_excl, phi, n_steps=3000, seed=trial, variant=variant)
        assert len({tuple(e) for e in events}) == len(events)
        for a, w in zip(events, lw):
            excl = a[a >= 0]
            assert len(set(excl)) == len(excl)
            assert w == pytest.approx(naive_log_weight(score, n_obj, n_excl, phi, a), abs=1e-10)
        assert np.all(np.isfinite(lw))


@pytest.mark.parametrize("variant", MCMC_VARIANTS)
def test_chain_plus_completion_finds_every_heavy_child(variant):
    """Every event with normalised weight > 1e-6 is found (M, m <= 5, one birth column)."""
    rng = np.random.default_rng(2)
    for trial in range(6):
        m, n_obj = int(rng.integers(1, 5)), int(rng.integers(0, 5))
        score, n_excl, phi = random_problem(rng, m, n_obj, 1, 1, forbid=0.0)
        all_ev = brute_force_events(m, n_excl, 1)
        all_lw = event_log_weights(score, n_obj, n_excl, phi, all_ev)
        p = np.exp(all_lw - np.logaddexp.reduce(all_lw[np.isfinite(all_lw)]))
        heavy = {tuple(e) for e in all_ev[p > 1e-6]}
        events, lw = mcmc_search(score, n_obj, n_excl, phi, n_steps=30000, seed=trial, variant=variant)
        events, lw = neighbour_completion(score, n_obj, n_excl, phi, events, lw, rounds=2)
        assert heavy <= {tuple(e) for e in events}
        np.testing.assert_allclose(lw, event_log_weights(score, n_obj, n_excl, phi, events), atol=1e-10)


def test_completion_adds_exactly_the_heavy_single_moves():
    """One round from one event = brute-force neighbours (paper move) above the threshold."""
    rng = np.random.default_rng(7)
    m, n_obj, n_birth = 4, 3, 1
    score, n_excl, phi = random_problem(rng, m, n_obj, n_birth, 2, forbid=0.0)
    start = np.array([0, -1, 3, -2])
    lw0 = event_log_weights(score, n_obj, n_excl, phi, start[None])
    tau = 1e-2
    ev, lw = neighbour_completion(score, n_obj, n_excl, phi, start[None], lw0, rounds=1, relative_threshold=tau)
    expected = set()
    for i in range(m):
        for c in list(range(n_excl)) + [-1, -2]:
            if c == start[i]:
                continue
            a = start.copy()
            if c >= 0:
                a[a == c] = -1  # the conflicting return goes to clutter
            a[i] = c
            w = naive_log_weight(score, n_obj, n_excl, phi, a)
            if w >= lw0[0] + np.log(tau):
                expected.add(tuple(a))
    assert {tuple(e) for e in ev[1:]} == expected
    assert tuple(ev[0]) == tuple(start)


def test_same_seed_same_result_and_seeds_differ():
    rng = np.random.default_rng(3)
    score, n_excl, phi = random_problem(rng, 6, 6, 0, 1, forbid=0.0)
    a = mcmc_search(score, 6, n_excl, phi, n_steps=2000, seed=11)
    b = mcmc_search(score, 6, n_excl, phi, n_steps=2000, seed=11)
    c = mcmc_search(score, 6, n_excl, phi, n_steps=2000, seed=12)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert a[0].shape != c[0].shape or not np.array_equal(a[0], c[0])


def test_reused_buffers_give_the_fresh_search():
    """A search reuses the previous search's buffers (table emptied slot by slot): interleaving
    other problems of the same and other shapes, including a completion that grows the buffers,
    must leave every result equal to the first run of the same problem."""
    import hypotrack.association.samplers.visited as vs

    rng = np.random.default_rng(5)
    problems = [random_problem(rng, m, 4, 1, 1, forbid=0.1) for m in (5, 5, 3)]
    kw = dict(n_steps=3000, burn_in=100, seed=7)
    first = [mcmc_search(s, 4, n_excl, phi, completion_rounds=r, **kw)
             for (s, n_excl, phi), r in zip(problems, (0, 2, 1))]
    assert vs._BUFFERS.pool is not None and np.all(vs._BUFFERS.pool[-1] == -1)  # handed back empty
    for _ in range(2):
        for (s, n_excl, phi), r, (ev, lw) in zip(problems, (0, 2, 1), first):
            ev2, lw2 = mcmc_search(s, 4, n_excl, phi, completion_rounds=r, **kw)
            np.testing.assert_array_equal(ev, ev2)
            np.testing.assert_array_equal(lw, lw2)


def test_burn_in_and_init():
    rng = np.random.default_rng(4)
    score, n_excl, phi = random_problem(rng, 3, 3, 0, 1, forbid=0.0)
    init = np.array([2, -1, 0])
    ev, lw = mcmc_search(score, 3, n_excl, phi, n_steps=0, seed=0, init=init)
    np.testing.assert_array_equal(ev, init[None])
    assert lw[0] == pytest.approx(naive_log_weight(score, 3, n_excl, phi, init))
    ev, _ = mcmc_search(score, 3, n_excl, phi, n_steps=50, burn_in=50, seed=0)
    assert len(ev) == 1  # only the state at the end of burn-in


def test_large_scan_copes():
    """m = 120 returns and 120 objects: far beyond any enumeration, the chain still runs."""
    rng = np.random.default_rng(5)
    n = 120
    score = rng.normal(size=(n, n + 1)) - 5.0
    perm = rng.permutation(n)
    score[np.arange(n), perm] = 5.0
    # every other entry, clutter included, is below 5 in its row: `perm` is the unique best event
    off = score.copy()
    off[np.arange(n), perm] = -np.inf
    assert off.max() < 5.0
    phi = np.zeros((n + 1, 1))
    ev, lw = mcmc_search(score, n, n, phi, n_steps=200_000, seed=1, burn_in=0)
    assert np.all(np.isfinite(lw))
    np.testing.assert_array_equal(ev[np.argmax(lw)], perm)  # the chain reaches the known best event
    assert lw.max() == pytest.approx(5.0 * n, abs=1e-9)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(n_steps=-1), "n_steps"),
        (dict(variant="gibbsy"), "variant"),
        (dict(burn_in=99), "burn_in"),
        (dict(init=np.array([0, 0])), "same exclusive column"),
        (dict(init=np.array([-1, 1])), "finite log-weight"),
    ],
)
def test_bad_input(kwargs, match):
    score = np.array([[0.0, 0.0, -1.0], [0.0, -np.inf, -1.0]])
    phi = np.zeros((3, 1))
    args = dict(n_steps=10, seed=0)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        mcmc_search(score, 2, 2, phi, **args)


def test_bad_problem_shapes():
    with pytest.raises(ValueError, match="count_term"):
        mcmc_search(np.zeros((2, 3)), 2, 2, np.zeros((2, 2)), n_steps=1, seed=0)
    with pytest.raises(ValueError, match="clutter"):
        mcmc_search(np.array([[0.0, -np.inf]]), 1, 1, np.zeros((2, 1)), n_steps=1, seed=0)
    with pytest.raises(ValueError, match="NaN"):
        mcmc_search(np.array([[np.nan, 0.0]]), 1, 1, np.zeros((2, 1)), n_steps=1, seed=0)


def _events_with_at_most(m, n_obj, detections):
    ev = brute_force_events(m, n_obj, 1)
    return {tuple(e) for e in ev if (e >= 0).sum() <= detections}


@pytest.mark.parametrize("rounds, count", [(0, 1), (1, 17), (2, 89), (3, 185)])
def test_completion_adds_one_detection_per_round_on_a_flat_problem(rounds, count):
    """All events weigh the same (zero scores, zero count term), so every single move passes the
    threshold: from the all-clutter event round r adds exactly the events with r detections.
    m = 4 returns, 4 objects: 1, 16, C(4,2)·4·3 = 72 and C(4,3)·4·3·2 = 96 events with 0..3
    detections. From one event the visited set starts with room for 68 (it must grow)."""
    m = n_obj = 4
    score, phi = np.zeros((m, n_obj + 1)), np.zeros((n_obj + 1, 1))
    start = np.full((1, m), -1)
    ev, lw = neighbour_completion(score, n_obj, n_obj, phi, start, [0.0], rounds=rounds)
    assert len(ev) == count and {tuple(e) for e in ev} == _events_with_at_most(m, n_obj, rounds)
    assert tuple(ev[0]) == (-1,) * m and ev.dtype == np.int32
    np.testing.assert_array_equal(lw, np.zeros(count))


def test_completion_default_is_two_rounds():
    m = n_obj = 4
    score, phi = np.zeros((m, n_obj + 1)), np.zeros((n_obj + 1, 1))
    ev, _ = neighbour_completion(score, n_obj, n_obj, phi, np.full((1, m), -1), [0.0])
    assert {tuple(e) for e in ev} == _events_with_at_most(m, n_obj, 2)


def test_completion_of_a_single_return():
    """m = 1: return 0 on clutter (weight 0) has neighbours object 0 (log 1) and object 1 (log -30);
    with relative threshold 1e-9 (log -20.7) only object 0 is added."""
    score = np.array([[1.0, -30.0, 0.0]])
    phi = np.zeros((3, 1))
    ev, lw = neighbour_completion(score, 2, 2, phi, [[-1]], [0.0], rounds=1)
    np.testing.assert_array_equal(ev, [[-1], [0]])
    np.testing.assert_allclose(lw, [0.0, 1.0])


def test_completion_with_no_rounds_returns_its_input_typed():
    events = [[0, -1], [-1, 1]]
    ev, lw = neighbour_completion(np.zeros((2, 3)), 2, 2, np.zeros((3, 1)), events, [0, -2], rounds=0)
    assert ev.dtype == np.int32 and lw.dtype == np.float64
    np.testing.assert_array_equal(ev, events)
    np.testing.assert_array_equal(lw, [0.0, -2.0])


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(rounds=-1), r"^rounds must be an integer in \[0, inf\], got -1$"),
        (dict(relative_threshold=0.0), r"^relative_threshold must lie in \(0, 1\), got 0\.0$"),
        (dict(relative_threshold=1.0), r"^relative_threshold must lie in \(0, 1\), got 1\.0$"),
    ],
)
def test_completion_bad_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        neighbour_completion(np.zeros((1, 2)), 1, 1, np.zeros((2, 1)), [[-1]], [0.0], **kwargs)


def test_init_given_as_whole_floats_is_read_as_event_codes():
    rng = np.random.default_rng(4)
    score, n_excl, phi = random_problem(rng, 3, 3, 0, 1, forbid=0.0)
    a = mcmc_search(score, 3, n_excl, phi, n_steps=200, seed=3, init=np.array([2, -1, 0]))
    b = mcmc_search(score, 3, n_excl, phi, n_steps=200, seed=3, init=np.array([2.0, -1.0, 0.0]))
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])


def test_paper_proposal_sends_the_displaced_return_to_clutter_symmetric_swaps():
    """Returns 0 and 1 hold objects 0 and 1 (log-weight 0); the swapped event weighs 10 and any
    event with clutter about -1000. The paper's move of return 0 to object 1 sends return 1 to
    clutter (rejected), so the paper chain, like Gibbs (object 1 is taken), never leaves its start;
    the symmetric move swaps the two and finds the heavier event."""
    score = np.array([[0.0, 5.0, -1000.0], [5.0, 0.0, -1000.0]])
    phi = np.zeros((3, 1))
    for variant in ("paper", "gibbs"):
        ev, lw = mcmc_search(score, 2, 2, phi, n_steps=300, seed=0, init=[0, 1], variant=variant)
        np.testing.assert_array_equal(ev, [[0, 1]])
        np.testing.assert_array_equal(lw, [0.0])
    ev, lw = mcmc_search(score, 2, 2, phi, n_steps=300, seed=0, init=[0, 1], variant="symmetric")
    np.testing.assert_array_equal(ev, [[0, 1], [1, 0]])
    np.testing.assert_array_equal(lw, [0.0, 10.0])


@pytest.mark.parametrize("barrier", ["score", "count_term"])
def test_temperature_two_crosses_a_barrier_and_keeps_exact_weights(barrier):
    """One return, one object: detecting it costs 16 in log-weight (in the score or in the count
    term). Over 10^5 steps the chain at T = 1 proposes it ~5·10^4 times and accepts each with
    e^-16 (~0.006 acceptances expected); at T = 2 with e^-8 (~17 expected). The weight recorded is
    the exact -16 whatever T."""
    score = np.array([[-16.0, 0.0]]) if barrier == "score" else np.zeros((1, 2))
    phi = np.zeros((2, 1)) if barrier == "score" else np.array([[0.0], [-16.0]])
    ev, lw = mcmc_search(score, 1, 1, phi, n_steps=100_000, seed=1)
    np.testing.assert_array_equal(ev, [[-1]])
    ev, lw = mcmc_search(score, 1, 1, phi, n_steps=100_000, seed=1, temperature=2.0)
    np.testing.assert_array_equal(ev, [[-1], [0]])
    np.testing.assert_array_equal(lw, [0.0, -16.0])


def _in_fresh_thread(fn):
    """fn() in a new thread: its thread-local buffers and key cache start empty."""
    import threading

    out = {}
    t = threading.Thread(target=lambda: out.setdefault("result", fn()))
    t.start()
    t.join()
    return out["result"]


def test_search_in_a_fresh_thread_equals_the_main_thread():
    rng = np.random.default_rng(8)
    score, n_excl, phi = random_problem(rng, 4, 3, 1, 1)

    def run():
        ev, lw = mcmc_search(score, 3, n_excl, phi, n_steps=2000, seed=5, completion_rounds=2)
        return neighbour_completion(score, 3, n_excl, phi, ev[:1], lw[:1], rounds=1) + (ev, lw)

    main, fresh = run(), _in_fresh_thread(run)
    for a, b in zip(main, fresh):
        np.testing.assert_array_equal(a, b)


def test_zobrist_keys_drawn_once_per_shape_deterministic_and_bounded(monkeypatch):
    import hypotrack.association.samplers.visited as vs

    monkeypatch.setattr(vs._BUFFERS, "zobrist", {}, raising=False)
    z = vs.zobrist_keys(10, 12)
    assert z.shape == (10, 12) and z.dtype == np.int64
    assert vs.zobrist_keys(10, 12) is z  # reused, not redrawn
    assert vs.zobrist_keys(12, 10).shape == (12, 10)  # another shape, other keys
    assert len(np.unique(z)) == z.size and (z < 0).any() and (z > 0).any()  # 64-bit keys, both signs
    monkeypatch.setattr(vs._BUFFERS, "zobrist", {})
    again = vs.zobrist_keys(10, 12)
    assert again is not z
    np.testing.assert_array_equal(again, z)  # a fresh cache draws the same keys
    cache = vs._BUFFERS.zobrist
    for n_col in range(1, vs._ZOBRIST_CACHE_SIZE):  # with (10, 12): the cache is full
        vs.zobrist_keys(1, n_col)
    assert len(cache) == vs._ZOBRIST_CACHE_SIZE
    vs.zobrist_keys(2, 1)  # one shape more: the cache is emptied first
    assert len(cache) == 1


def test_buffers_of_equal_capacity_are_reused_and_others_are_not(monkeypatch):
    """A search hands its buffers to the next search of the same capacity (same row store), not to
    one whose rows do not fit; a reused search that grows its buffers during the completion gives
    the same events as in a fresh thread."""
    import hypotrack.association.samplers.visited as vs

    monkeypatch.setattr(vs._BUFFERS, "pool", None, raising=False)
    m = n_obj = 4
    score, phi = np.zeros((m, n_obj + 1)), np.zeros((n_obj + 1, 1))
    mcmc_search(score, n_obj, n_obj, phi, n_steps=20, seed=0)
    store = vs._BUFFERS.pool[1]
    assert vs._BUFFERS.pool[0] == 21  # capacity n_steps - burn_in + 1

    def grown():  # 20 steps record at most 21 events; two completion rounds reach far more
        return mcmc_search(score, n_obj, n_obj, phi, n_steps=20, seed=1, completion_rounds=2)

    ev, lw = grown()
    assert vs._BUFFERS.pool[1] is not store  # the reused store was replaced by a grown one
    ev_fresh, lw_fresh = _in_fresh_thread(grown)
    np.testing.assert_array_equal(ev, ev_fresh)
    np.testing.assert_array_equal(lw, lw_fresh)
    assert len(ev) > 21
    mcmc_search(score, n_obj, n_obj, phi, n_steps=20, seed=2)
    store = vs._BUFFERS.pool[1]
    mcmc_search(score, n_obj, n_obj, phi, n_steps=20, seed=3)
    assert vs._BUFFERS.pool[1] is store  # same capacity and m: the same row store
    wide = np.zeros((6, n_obj + 1))
    ev6, lw6 = mcmc_search(wide, n_obj, n_obj, phi, n_steps=20, seed=3)  # 6 rows per event: too big
    assert vs._BUFFERS.pool[1] is not store
    ev6_fresh, _ = _in_fresh_thread(lambda: mcmc_search(wide, n_obj, n_obj, phi, n_steps=20, seed=3))
    np.testing.assert_array_equal(ev6, ev6_fresh)


_BAD_SEARCH = [
    (dict(init=[0, 2]), r"^init codes must lie in \[-1, 1\], got \[0, 2\]$"),  # 2 is no column, not clutter
    (dict(init=[-2, 0]), r"^init codes must lie in \[-1, 1\], got \[-2, 0\]$"),
    (dict(init=[0, 0, 1]), r"^init must have shape \(2,\), got \(3,\)$"),
    (dict(init=[1, 1]), "^init assigns two returns to the same exclusive column$"),
    (dict(init=[-1, 1]), r"^init must have a finite log-weight \(a feasible event\)$"),
    (dict(burn_in=-1), r"^burn_in must be an integer in \[0, 10\], got -1$"),
    (dict(burn_in=11), r"^burn_in must be an integer in \[0, 10\], got 11$"),
    (dict(seed=-1), r"^seed must be an integer in \[0, inf\], got -1$"),
    (dict(completion_rounds=-1), r"^completion_rounds must be an integer in \[0, inf\], got -1$"),
    (dict(completion_threshold=0.0), r"^completion_threshold must lie in \(0, 1\), got 0\.0$"),
    (dict(completion_threshold=1.0), r"^completion_threshold must lie in \(0, 1\), got 1\.0$"),
]


@pytest.mark.parametrize("kwargs, message", _BAD_SEARCH)
def test_search_messages_name_the_argument_and_its_range(kwargs, message):
    score = np.array([[0.0, 0.0, -1.0], [0.0, -np.inf, -1.0]])  # 2 objects, clutter; return 1 not on object 1
    with pytest.raises(ValueError, match=message):
        mcmc_search(score, 2, 2, np.zeros((3, 1)), **{"n_steps": 10, "seed": 0, **kwargs})


def test_init_may_put_several_returns_on_clutter():
    score = np.zeros((3, 3))
    ev, lw = mcmc_search(score, 2, 2, np.zeros((3, 1)), n_steps=0, seed=0, init=[-1, 1, -1])
    np.testing.assert_array_equal(ev, [[-1, 1, -1]])


def test_every_step_to_a_new_event_fills_the_visited_set_exactly():
    """One return, 1000 equally weighted objects: every proposal is accepted and, for this seed,
    each of the 3 steps reaches a new event (a revisit has probability ~3e-3), so 4 = n_steps + 1
    events are recorded: the visited set must hold exactly that many."""
    score = np.zeros((1, 1001))
    ev, lw = mcmc_search(score, 1000, 1000, np.zeros((1001, 1)), n_steps=3, seed=0)
    assert len(ev) == 4 and len({tuple(e) for e in ev}) == 4 and ev[0, 0] == -1
    np.testing.assert_array_equal(lw, np.zeros(4))


@pytest.mark.parametrize(
    "events, message",
    [
        (np.zeros((2, 2), dtype=int), r"^events must have shape \(E, 3\), got \(2, 2\)$"),
        (np.array([[0, 0, 2]]), r"^event codes must lie in \[-2, 1\], got \[0, 2\]$"),  # 2 = n_exclusive
        (np.array([[0, -3, 1]]), r"^event codes must lie in \[-2, 1\], got \[-3, 1\]$"),
    ],
)
def test_event_log_weights_checks_shape_and_codes(events, message):
    score = np.zeros((3, 4))  # 2 exclusive columns, clutter and one more row option
    with pytest.raises(ValueError, match=message):
        event_log_weights(score, 1, 2, np.zeros((2, 2)), events)


def test_event_log_weights_reads_exact_rationals_as_numbers():
    from fractions import Fraction

    score = [[Fraction(1, 2), Fraction(-1, 4)], [Fraction(3, 2), Fraction(0)]]  # 1 object, clutter
    lw = event_log_weights(score, 1, 1, [[Fraction(0)], [Fraction(-1)]], np.array([[0, -1], [-1, 0], [-1, -1]]))
    np.testing.assert_array_equal(lw, [0.5 + 0.0 - 1.0, -0.25 + 1.5 - 1.0, -0.25])


def test_buffered_stream_is_numbas_np_random():
    """The chain's local generator (hypotrack.association.mt19937) must be numba's np.random
    stream bit for bit: NumPy's legacy RandomState (the same MT19937 seeding and 53-bit
    doubles) is the independent oracle, over several refills of the buffer."""
    import numba

    from hypotrack.association.mt19937 import N_DOUBLES, doubles

    @numba.njit
    def numba_stream(seed, n):
        np.random.seed(seed)
        out = np.empty(n)
        for j in range(n):
            out[j] = np.random.random()
        return out

    n = 3 * N_DOUBLES + 5
    for seed in (0, 1, 20261121, 2**32 - 1):
        ours = doubles(seed, n)
        np.testing.assert_array_equal(ours.view(np.int64), np.random.RandomState(seed).random_sample(n).view(np.int64))
        np.testing.assert_array_equal(ours.view(np.int64), numba_stream(seed, n).view(np.int64))


def reference_chain(score, n_obj, n_excl, phi, init, n_steps, burn_in, symmetric, uniform):
    """Document 000's chain (paper or symmetric swap) step by step in Python: the proposals, the
    Metropolis test ``log U < Δ`` and the running log-weight, recording distinct events after
    burn-in in first-visit order."""
    m, n_col = score.shape
    state = [c if c >= 0 else n_excl - 1 - c for c in init]

    def counts(st):
        return sum(c < n_obj for c in st), sum(n_obj <= c < n_excl for c in st)

    lw = sum(score[i, c] for i, c in enumerate(state)) + phi[counts(state)]
    found, order = {}, []

    def record():
        key = tuple(c if c < n_excl else n_excl - 1 - c for c in state)
        if key not in found:
            found[key] = lw
            order.append(key)

    if burn_in == 0:
        record()
    for step in range(1, n_steps + 1):
        moved = False
        i = int(uniform() * m)
        cur = state[i]
        c = int(uniform() * n_col)
        if c != cur:
            new = list(state)
            new[i] = c
            if c < n_excl and c in state:
                i2 = state.index(c)
                new[i2] = cur if symmetric else n_excl
            # the kernel's order of operations: score change, then the count-term change
            delta = score[i, c] - score[i, cur]
            if c < n_excl and c in state:
                delta += score[i2, new[i2]] - score[i2, c]
            delta += phi[counts(new)] - phi[counts(state)]
            accept = delta >= 0 or np.log(uniform()) < delta
            if accept:
                lw += delta
                state = new
                moved = True
        if step == burn_in or (moved and step > burn_in):
            record()
    return np.array(order, dtype=np.int64).reshape(len(order), m), np.array([found[k] for k in order])


@pytest.mark.parametrize("variant", ["paper", "symmetric"])
def test_chain_is_the_step_by_step_reference(variant):
    """The compiled chain visits exactly the events of the Python reference, in the same order
    and with the same running log-weights (same uniforms, same decisions): births, forbidden
    pairs, conflicts with a held column and a forbidden count all occur."""
    rng = np.random.default_rng(8)
    score, n_excl, phi = random_problem(rng, 5, 4, 2, 1, forbid=0.3)
    score[:, :n_excl] += 1.5  # assignments compete with clutter: many moves and conflicts
    init = np.full(5, -1)
    seed = 1234
    chain_seed = int(np.random.SeedSequence(seed).generate_state(2, dtype=np.uint32)[1])
    ref_rng = np.random.RandomState(chain_seed)
    ev_ref, lw_ref = reference_chain(score, 4, n_excl, phi, init, 4000, 200, variant == "symmetric",
                                     ref_rng.random_sample)
    ev, lw = mcmc_search(score, 4, n_excl, phi, n_steps=4000, burn_in=200, seed=seed, variant=variant, init=init)
    assert len(ev_ref) > 20
    np.testing.assert_array_equal(ev, ev_ref)
    np.testing.assert_array_equal(lw, lw_ref)


_BAD_PROBLEMS = [
    (np.zeros(3), 0, 0, np.zeros((1, 1)), r"^score must be a 2-D \(m, n_exclusive \+ n_options\) array, got shape \(3,\)$"),
    (np.zeros((2, 3)), 1, 3, np.zeros((2, 3)), r"^n_exclusive must be an integer in \[0, 2\], got 3$"),
    (np.zeros((2, 3)), 0, -1, np.zeros((1, 1)), r"^n_exclusive must be an integer in \[0, 2\], got -1$"),
    (np.zeros((2, 3)), 3, 2, np.zeros((4, 1)), r"^n_objects must be an integer in \[0, 2\], got 3$"),
    (np.zeros((2, 3)), -1, 2, np.zeros((1, 1)), r"^n_objects must be an integer in \[0, 2\], got -1$"),
    (np.zeros((2, 0)), 0, 0, np.zeros((1, 1)),
     r"^score needs at least one row-option column \(clutter\) after the exclusive columns$"),
    (np.array([[0.0, np.nan, 0.0]]), 1, 2, np.zeros((2, 2)),
     r"^score must not contain NaN or \+inf \(use -inf for forbidden pairs\)$"),
    (np.array([[0.0, np.inf, 0.0]]), 1, 2, np.zeros((2, 2)),
     r"^score must not contain NaN or \+inf \(use -inf for forbidden pairs\)$"),
    (np.array([[0.0, 0.0, -np.inf]]), 1, 2, np.zeros((2, 2)),
     r"^score's clutter column \(index n_exclusive\) must be finite: clutter must always be possible$"),
    (np.zeros((1, 3)), 1, 2, np.zeros((2, 1)),
     r"^count_term must have shape \(n_objects \+ 1, n_exclusive - n_objects \+ 1\) = \(2, 2\), got \(2, 1\)$"),
    (np.zeros((1, 3)), 1, 2, np.array([[0.0, np.nan], [0.0, 0.0]]), r"^count_term must not contain NaN or \+inf$"),
    (np.zeros((1, 3)), 1, 2, np.array([[0.0, np.inf], [0.0, 0.0]]), r"^count_term must not contain NaN or \+inf$"),
]


@pytest.mark.parametrize("score, n_obj, n_excl, phi, message", _BAD_PROBLEMS)
def test_problem_messages_name_the_argument_and_the_rule(score, n_obj, n_excl, phi, message):
    m = score.shape[0] if score.ndim == 2 else 1
    with pytest.raises(ValueError, match=message):
        event_log_weights(score, n_obj, n_excl, phi, np.full((1, m), -1))


def test_empty_scan_needs_no_clutter_column():
    """m = 0: no return needs clutter; the one (empty) event weighs the count term φ[0, 0]."""
    lw = event_log_weights(np.zeros((0, 0)), 0, 0, [[0.25]], np.zeros((1, 0), dtype=int))
    np.testing.assert_array_equal(lw, [0.25])


def test_single_column_problem_has_no_exclusive_column():
    """With one column that column is clutter: n_exclusive may only be 0."""
    with pytest.raises(ValueError, match=r"^n_exclusive must be an integer in \[0, 0\], got 1$"):
        event_log_weights(np.zeros((0, 1)), 0, 1, np.zeros((1, 2)), np.zeros((1, 0), dtype=int))
