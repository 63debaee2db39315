"""numba's ``np.random.random`` stream as a local, buffered generator for compiled chains.

A compiled MCMC chain (:mod:`.samplers.chain`) draws two or three uniforms per proposal. numba's
``np.random.random()`` reads the thread's Mersenne Twister state through a pointer, tempers two
32-bit words and converts them one draw at a time; here the state lives in a local array and
every refill of 624 words is tempered and converted in one loop into 312 doubles, which the
chain then reads one by one. The stream is bit for bit numba's (and NumPy's legacy
``RandomState``): ``seed_state(s)`` is ``np.random.seed(s)`` (MT19937 ``init_genrand`` with a
32-bit seed), each double is ``((w₁ >> 5) · 2²⁶ + (w₂ >> 6)) / 2⁵³`` of two tempered words, so
a chain that switches from ``np.random.random()`` to the buffer makes the same decisions (tests compare the two streams draw by draw).

Reference: Matsumoto & Nishimura, "Mersenne Twister", ACM TOMACS 8 (1998); numba ``_random.c``.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["N_DOUBLES", "seed_state", "fill_doubles", "doubles"]

_MT_N = 624
_MT_M = 397
_MASK32 = 0xFFFFFFFF
N_DOUBLES = _MT_N // 2  # doubles per refill (two words each; a stream never splits a pair)


@numba.njit(cache=True, nogil=True)
def seed_state(seed):
    """MT19937 state after ``init_genrand(seed & 0xffffffff)`` (numba's ``np.random.seed``).

    Words are held in int64 (always < 2³²): int64 → double conversion is one instruction.
    """
    mt = np.empty(_MT_N, dtype=np.int64)
    s = np.int64(seed) & _MASK32
    for pos in range(_MT_N):
        mt[pos] = s
        s = (1812433253 * (s ^ (s >> 30)) + pos + 1) & _MASK32
    return mt


@numba.njit(cache=True, nogil=True)
def _twist(mt):
    upper = np.int64(0x80000000)
    lower = np.int64(0x7FFFFFFF)
    matrix_a = np.int64(0x9908B0DF)
    for i in range(_MT_N - _MT_M):
        y = (mt[i] & upper) | (mt[i + 1] & lower)
        mt[i] = mt[i + _MT_M] ^ (y >> 1) ^ (-(y & 1) & matrix_a)
    for i in range(_MT_N - _MT_M, _MT_N - 1):
        y = (mt[i] & upper) | (mt[i + 1] & lower)
        mt[i] = mt[i + _MT_M - _MT_N] ^ (y >> 1) ^ (-(y & 1) & matrix_a)
    y = (mt[_MT_N - 1] & upper) | (mt[0] & lower)
    mt[_MT_N - 1] = mt[_MT_M - 1] ^ (y >> 1) ^ (-(y & 1) & matrix_a)


@numba.njit(cache=True, nogil=True, inline="always")
def _temper(y):
    y ^= y >> 11
    y ^= (y << 7) & np.int64(0x9D2C5680)
    y ^= (y << 15) & np.int64(0xEFC60000)
    y ^= y >> 18
    return y


@numba.njit(cache=True, nogil=True)
def fill_doubles(mt, buf):
    """Advance the state by 624 words into ``buf``'s 312 doubles in [0, 1)."""
    _twist(mt)
    for j in range(N_DOUBLES):
        a = _temper(mt[2 * j]) >> 5
        b = _temper(mt[2 * j + 1]) >> 6
        buf[j] = (float(a) * 67108864.0 + float(b)) / 9007199254740992.0


@numba.njit(cache=True, nogil=True)
def doubles(seed, n):
    """The first ``n`` uniforms of the stream seeded with ``seed``, read as a chain reads them:
    a buffer of :data:`N_DOUBLES` refilled when used up (numba would inline a small reader
    function returning ``(u, position)``, but such tuple returns cost the chain 4× its time)."""
    mt = seed_state(seed)
    buf = np.empty(N_DOUBLES)
    pos = N_DOUBLES
    out = np.empty(n)
    for j in range(n):
        if pos >= N_DOUBLES:
            fill_doubles(mt, buf)
            pos = 0
        out[j] = buf[pos]
        pos += 1
    return out
