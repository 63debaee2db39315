"""Compiled EKF replay of :class:`~.orbit3d.J2Orbit3D`: many tracks, each predicted over its own gap in its own
number of equal steps, mean, state-transition matrix and covariance, in one kernel call.

The lazy factored filter's replay (:func:`hypotrack.hypotheses.factored.lane.predict_each` with ``step``) predicts a
track woken after a gap of ``k`` scans in ``k`` EKF steps ``x ← f(x)``, ``P ← sym(Φ P Φᵀ + Q(h))``
(``sym(A) = (A + Aᵀ)/2``, ``Q`` the white-acceleration noise ``q [[h³/3 I, h²/2 I], [h²/2 I, h I]]``,
:meth:`~.orbit.TwoBodyOrbit.Q`). In array passes that is one numpy batch per step: ~30 array operations on the
complex-step rows each, so a track re-acquired after an orbit out of view (~570 scans of 10 s) costs ~570 Python
round trips. :func:`replay_j2` runs the same arithmetic row by row in one compiled pass.

The same arithmetic: ``Φ`` is the complex-step derivative of the RK4 map (:meth:`~.orbit3d.J2Orbit3D.transition`:
six copies of the state, copy ``j`` perturbed by ``i·h`` in component ``j``, through the same RK4 steps, ``Φ[:, j]``
their imaginary parts over ``h``), written out on (real, imaginary) pairs with numpy's complex formulas —
product ``(ac − bd, ad + bc)``, quotient by Smith's scaling (``rat = d/c``, ``scl = 1/(c + d·rat)``, as numpy's
loop), square root ``t = sqrt((a + hypot(a, b))/2)``, ``b/(2t)`` — and the mean is the real part of the first copy,
as there. The imaginary parts are ~1e-30 of the real ones, so they never reach a real part (``bd``, ``d·rat`` and
``b`` in ``hypot(a, b)`` are below half an ulp of what they are added to): the six copies share one real part,
computed once per RK4 stage, and only their imaginary parts are carried six times — the same numbers as six
full complex runs (a third of their cost). The six imaginary parts (and two idle copies) run in the lanes of one
vector (:func:`_rk4`: a copy per lane, the same IEEE operations lane by lane), and a row's covariance stays in a
local 6 × 6 over its steps: ~0.17 µs per EKF step on this machine (~0.21 copy by copy, measured side by side).

Tracks side by side (:func:`replay_lanes`, what :func:`replay_j2` runs). One track at a time (:func:`_replay_row`),
each EKF step's real RK4 part is a chain of dependent divisions and square roots (each stage's acceleration waits on
the last) and ``Φ P Φᵀ`` chains of fused multiply-adds: the processor mostly waits on latencies. :func:`replay_lanes`
runs ``LANES`` tracks at once, every quantity of the step a row of one flat workspace (row ``r``, lane ``l`` at
``r·LANES + l``) and every operation a loop over the lanes, innermost, over one array at constant distances, with a
trip count known only when run (a known 8 would be unrolled into scalar code): the compiler makes each loop vector
instructions, each lane its track's own IEEE operations in the same order, so the same numbers as track by track, bit
for bit on any machine (``tests/unit/models/test_orbit3d_replay_rows.py``). A lane takes its step while ``step < k``
and keeps its moments after (a select, no arithmetic on them), so a group costs its longest track's steps;
:func:`replay_j2` groups the tracks by RK4 substeps per step and then by ``k``, longest first, and a group whose lanes
would mostly idle goes track by track (``LANE_GROUP_COST``). Measured side by side on this machine: ~0.066 µs per
EKF step and track in full groups, ~0.18 track by track (~0.21 before either).

Rounding. numpy's vectorised complex product rounds ``ad + bc`` as one fused multiply-add ``fma(a, d, b·c)``, and
OpenBLAS's 6 × 6 product accumulates ``Σ_k a_ik b_kj`` as a chain of fused multiply-adds in ``k`` order; the kernel
does the same (:func:`_fma`), so on a machine where numpy and its BLAS take those paths (x86-64 with FMA: measured
here, AVX-512) the means, ``Φ`` and the covariances are bit for bit the array passes' (:func:`rounds_as_numpy` tells;
the tests assert it then). Elsewhere (another BLAS, no FMA) they agree to rounding: the means still bit for bit,
the covariances to ~1e-13 of their scale after hundreds of steps.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic

from .._validation import check_finite_array

__all__ = ["replay_j2", "replay_lanes", "rounds_as_numpy", "fused_multiply_add", "LANES", "LANE_GROUP_COST"]


@intrinsic
def _fma(typingctx, a, b, c):
    """``a·b + c`` rounded once (LLVM's ``llvm.fma.f64``): the fused multiply-add numpy's vectorised complex product
    and OpenBLAS's small-matrix product use (module docstring)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        d = ir.DoubleType()
        return builder.call(cgutils.get_or_insert_function(builder.module, ir.FunctionType(d, [d, d, d]), "llvm.fma.f64"),
                            args)

    return sig, codegen


#: :func:`_fma` for the other compiled kernels that round as numpy's BLAS (e.g. the radar's EKF moments)
fused_multiply_add = _fma


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _acc_re(xr, yr, zr, mu, c_j2):
    """Real parts of :func:`~.orbit3d._j2_acceleration` at a complex position of real part ``(xr, yr, zr)`` (module
    docstring: the imaginary parts do not reach them) and the real intermediates :func:`_acc_im` needs."""
    dr = (xr * xr + yr * yr) + zr * zr
    ir2r = (1.0 + 0.0) * (1.0 / dr)
    t = math.sqrt((ir2r + ir2r) * 0.5)  # sqrt((a + hypot(a, b)) / 2), hypot(a, b) = a for |b| <= 2^-60 |a|
    ir3r = ir2r * t
    kjr = c_j2 * ir2r
    a5 = 5.0 * zr * zr
    s_r = a5 * ir2r
    A1 = kjr * (s_r - 1.0) - mu
    A3 = kjr * (s_r - 3.0) - mu
    fr, gr = ir3r * A1, ir3r * A3
    return (xr * fr, yr * fr, zr * gr), (dr, ir2r, t, ir3r, kjr, a5, s_r, A1, A3, fr, gr)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _acc_im(xr, yr, zr, xi, yi, zi, q, c_j2):
    """Imaginary parts of :func:`~.orbit3d._j2_acceleration` at ``(xr + i xi, …)``, numpy's complex formulas term for
    term: a product's ``ad + bc``, the quotient's ``(0 − 1·rat)·scl`` (``rat = d/c``), the root's ``b/(2t)``;
    ``q`` the real intermediates (:func:`_acc_re`)."""
    dr, ir2r, t, ir3r, kjr, a5, s_r, A1, A3, fr, gr = q
    di = (_fma(xr, xi, xi * xr) + _fma(yr, yi, yi * yr)) + _fma(zr, zi, zi * zr)
    ir2i = (0.0 - 1.0 * (di / dr)) * ir2r
    si = ir2i / (2.0 * t)
    ir3i = _fma(ir2r, si, ir2i * t)
    kji = c_j2 * ir2i
    s_i = _fma(a5, ir2i, _fma(5.0 * zr, zi, 5.0 * zi * zr) * ir2r)
    fi = _fma(ir3r, _fma(kjr, s_i, kji * (s_r - 1.0)), ir3i * A1)
    gi = _fma(ir3r, _fma(kjr, s_i, kji * (s_r - 3.0)), ir3i * A3)
    return _fma(xr, fi, xi * fr), _fma(yr, fi, yi * fr), _fma(zr, gi, zi * gr)


#: copies carried side by side in :func:`_rk4` (the six of the complex step and two idle ones, zero imaginary
#: parts): a power of two, so that the compiler runs the copies' identical arithmetic in vector lanes
_LANES = 8


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rk4(R, I, hk, mu, c_j2):
    """One RK4 step of ``hk`` (:func:`~.orbit3d._rk4_j2_arrays`'s) of the complex copies, in place: their common
    real part ``R`` ``(6,)`` once, each copy's imaginary part (the columns of ``I`` ``(6, _LANES)``: component, copy)
    with the same real intermediates, the same operations on each copy, one copy per vector lane (IEEE arithmetic
    lane by lane: the same numbers as copy by copy)."""
    hk2, hk6 = hk / 2, hk / 6
    rx, ry, rz, vx, vy, vz = R[0], R[1], R[2], R[3], R[4], R[5]
    (a1x, a1y, a1z), q1 = _acc_re(rx, ry, rz, mu, c_j2)
    v2x, v2y, v2z = vx + hk2 * a1x, vy + hk2 * a1y, vz + hk2 * a1z
    p2x, p2y, p2z = rx + hk2 * vx, ry + hk2 * vy, rz + hk2 * vz
    (a2x, a2y, a2z), q2 = _acc_re(p2x, p2y, p2z, mu, c_j2)
    v3x, v3y, v3z = vx + hk2 * a2x, vy + hk2 * a2y, vz + hk2 * a2z
    p3x, p3y, p3z = rx + hk2 * v2x, ry + hk2 * v2y, rz + hk2 * v2z
    (a3x, a3y, a3z), q3 = _acc_re(p3x, p3y, p3z, mu, c_j2)
    v4x, v4y, v4z = vx + hk * a3x, vy + hk * a3y, vz + hk * a3z
    p4x, p4y, p4z = rx + hk * v3x, ry + hk * v3y, rz + hk * v3z
    (a4x, a4y, a4z), q4 = _acc_re(p4x, p4y, p4z, mu, c_j2)
    for c in range(_LANES):
        rxi, ryi, rzi, vxi, vyi, vzi = I[0, c], I[1, c], I[2, c], I[3, c], I[4, c], I[5, c]
        b1x, b1y, b1z = _acc_im(rx, ry, rz, rxi, ryi, rzi, q1, c_j2)
        w2x, w2y, w2z = vxi + hk2 * b1x, vyi + hk2 * b1y, vzi + hk2 * b1z
        b2x, b2y, b2z = _acc_im(p2x, p2y, p2z, rxi + hk2 * vxi, ryi + hk2 * vyi, rzi + hk2 * vzi, q2, c_j2)
        w3x, w3y, w3z = vxi + hk2 * b2x, vyi + hk2 * b2y, vzi + hk2 * b2z
        b3x, b3y, b3z = _acc_im(p3x, p3y, p3z, rxi + hk2 * w2x, ryi + hk2 * w2y, rzi + hk2 * w2z, q3, c_j2)
        w4x, w4y, w4z = vxi + hk * b3x, vyi + hk * b3y, vzi + hk * b3z
        b4x, b4y, b4z = _acc_im(p4x, p4y, p4z, rxi + hk * w3x, ryi + hk * w3y, rzi + hk * w3z, q4, c_j2)
        I[0, c] = rxi + hk6 * ((vxi + 2 * (w2x + w3x)) + w4x)
        I[1, c] = ryi + hk6 * ((vyi + 2 * (w2y + w3y)) + w4y)
        I[2, c] = rzi + hk6 * ((vzi + 2 * (w2z + w3z)) + w4z)
        I[3, c] = vxi + hk6 * ((b1x + 2 * (b2x + b3x)) + b4x)
        I[4, c] = vyi + hk6 * ((b1y + 2 * (b2y + b3y)) + b4y)
        I[5, c] = vzi + hk6 * ((b1z + 2 * (b2z + b3z)) + b4z)
    R[0] = rx + hk6 * ((vx + 2 * (v2x + v3x)) + v4x)
    R[1] = ry + hk6 * ((vy + 2 * (v2y + v3y)) + v4y)
    R[2] = rz + hk6 * ((vz + 2 * (v2z + v3z)) + v4z)
    R[3] = vx + hk6 * ((a1x + 2 * (a2x + a3x)) + a4x)
    R[4] = vy + hk6 * ((a1y + 2 * (a2y + a3y)) + a4y)
    R[5] = vz + hk6 * ((a1z + 2 * (a2z + a3z)) + a4z)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _row_product(X, a, Y, out):
    """Row ``a`` of ``X Y`` (6 × 6 of ``(6, ≥ 6)`` arrays) into ``out``: entry ``b`` the chain
    ``s ← fma(X[a, j], Y[j, b], s)`` over ``j = 0..5`` from ``s = 0``, as OpenBLAS's small product (module
    docstring); ``X``'s row held in registers."""
    f0, f1, f2, f3, f4, f5 = X[a, 0], X[a, 1], X[a, 2], X[a, 3], X[a, 4], X[a, 5]
    for c in range(6):
        s = _fma(f1, Y[1, c], _fma(f0, Y[0, c], 0.0))
        s = _fma(f3, Y[3, c], _fma(f2, Y[2, c], s))
        out[a, c] = _fma(f5, Y[5, c], _fma(f4, Y[4, c], s))


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _replay_row(xo, Po, i, hi, ki, max_step, q, mu, c_j2, hstep):
    """Row ``i`` of ``xo`` ``(n, 6)``, ``Po`` ``(n, 6, 6)`` in ``ki`` EKF steps of ``hi``, in place (module docstring).
    Returns whether its prediction went non-finite (the row then as at that step).

    Per step, in this order (the array passes' operations): the copies through the RK4 (:func:`_rk4`), ``Φ[a, b]``
    their imaginary parts over ``h``, ``B = Φ P`` and ``A = B Φᵀ + Q`` as fused-multiply-add chains,
    ``P ← (A + Aᵀ)/2``. The covariance stays in a local 6 × 6 between the steps. The finiteness of the mean and
    ``Φ`` is tested branch-free (``Σ x·0``: 0 for finite ``x``, NaN for an infinite or NaN one) and decides as the
    test of each number did: a non-finite step stops the replay there."""
    # 6 × _LANES: each row's last columns idle (zeros), so that a row is one vector of the lanes' width
    R, Zi = np.empty(6), np.zeros((6, _LANES))
    Ft, A, B, C = np.zeros((6, _LANES)), np.zeros((6, _LANES)), np.zeros((6, _LANES)), np.zeros((6, _LANES))
    m = int(math.ceil(abs(hi) / max_step))
    hs = hi / max(m, 1)
    h3, h2 = q * (hi ** 3.0 / 3), q * (hi ** 2.0 / 2)
    h1 = q * hi
    for a in range(6):
        R[a] = xo[i, a]
        for b in range(6):
            C[a, b] = Po[i, a, b]
    bad = False
    for _ in range(ki):
        for a in range(6):
            for c in range(_LANES):
                Zi[a, c] = 0.0
            Zi[a, a] = hstep
        for _s in range(m):
            _rk4(R, Zi, hs, mu, c_j2)
        z = 0.0
        for a in range(6):  # Φ[a, b] = Zi[a, b] / h, in place
            z += R[a] * 0.0
            for c in range(_LANES):
                Zi[a, c] = Zi[a, c] / hstep
            for b in range(6):  # (the idle copies are no part of Φ)
                z += Zi[a, b] * 0.0
        for a in range(6):
            for b in range(6):
                Ft[b, a] = Zi[a, b]
        # B = Φ P, A = B Φᵀ (Ft = Φᵀ): entry (a, b) the chain s ← fma(x_j, y_j, s) over j = 0..5 from s = 0
        for a in range(6):
            _row_product(Zi, a, C, B)
        for a in range(6):
            _row_product(B, a, Ft, A)
        for a in range(3):
            A[a, a] += h3
            A[a, a + 3] += h2
            A[a + 3, a] += h2
            A[a + 3, a + 3] += h1
        for a in range(6):
            for b in range(6):
                C[a, b] = 0.5 * (A[a, b] + A[b, a])
        if z != 0.0:  # NaN: a mean or Φ entry not finite (this step's, where the array passes would stop)
            bad = True
            break
    for a in range(6):
        xo[i, a] = R[a]
        for b in range(6):
            Po[i, a, b] = C[a, b]
    return bad


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _replay(X, P, h, k, max_step, q, mu, c_j2, hstep):
    """Rows ``X`` ``(n, 6)``, ``P`` ``(n, 6, 6)``: row ``i`` in ``k[i]`` EKF steps of ``h[i]``, one row after the other
    (:func:`_replay_row`). Returns ``(x, P, bad)``: ``bad`` the first row whose prediction is not finite (−1: none)."""
    xo, Po = X.copy(), P.copy()
    for i in range(X.shape[0]):
        if k[i] > 0 and _replay_row(xo, Po, i, h[i], k[i], max_step, q, mu, c_j2, hstep):
            return xo, Po, i
    return xo, Po, -1


#: tracks run side by side (AVX-512's doubles per vector)
LANES = 8

#: a group's step in lanes costs about this many steps of one track alone (:func:`_replay_row`;
#: measured ~0.4–0.5 against ~0.18 µs): a group whose steps ``Σ k`` are fewer than this times its longest ``k`` is
#: replayed track by track (the same numbers either way)
LANE_GROUP_COST = 3

# rows of the workspace: the mean, the six copies' imaginary parts (copy c, component a: _I + 6 c + a), each RK4
# stage's position and real intermediates (_S + 14 s), the covariance, Φ, Φ P, Φ P Φᵀ + Q (6 × 6 each, row-major),
# each lane's substep, Q's three terms, steps to take, whether it steps now, whether its prediction went non-finite
_R, _I, _S, _C, _F, _B, _A = 0, 6, 42, 98, 134, 170, 206
_HS, _H3, _H2, _H1, _K, _ACT, _BAD = 242, 243, 244, 245, 246, 247, 248
_ROWS = 249


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _real_stages(W, mu, c_j2):
    """The RK4 step's real part for every lane (:func:`_rk4`'s), each stage's position and real
    intermediates kept for the imaginary parts; the mean moved only in the lanes that step."""
    nl = W.shape[0] // _ROWS  # = LANES, known only when run: a loop of a known 8 would be unrolled to scalars
    for l in range(nl):
        hk = W[_HS * LANES + l]
        hk2, hk6 = hk / 2, hk / 6
        rx, ry, rz, vx, vy, vz = W[0 * LANES + l], W[1 * LANES + l], W[2 * LANES + l], W[3 * LANES + l], W[4 * LANES + l], W[5 * LANES + l]
        (a1x, a1y, a1z), q1 = _acc_re(rx, ry, rz, mu, c_j2)
        v2x, v2y, v2z = vx + hk2 * a1x, vy + hk2 * a1y, vz + hk2 * a1z
        p2x, p2y, p2z = rx + hk2 * vx, ry + hk2 * vy, rz + hk2 * vz
        (a2x, a2y, a2z), q2 = _acc_re(p2x, p2y, p2z, mu, c_j2)
        v3x, v3y, v3z = vx + hk2 * a2x, vy + hk2 * a2y, vz + hk2 * a2z
        p3x, p3y, p3z = rx + hk2 * v2x, ry + hk2 * v2y, rz + hk2 * v2z
        (a3x, a3y, a3z), q3 = _acc_re(p3x, p3y, p3z, mu, c_j2)
        v4x, v4y, v4z = vx + hk * a3x, vy + hk * a3y, vz + hk * a3z
        p4x, p4y, p4z = rx + hk * v3x, ry + hk * v3y, rz + hk * v3z
        (a4x, a4y, a4z), q4 = _acc_re(p4x, p4y, p4z, mu, c_j2)
        _keep(W, _S, l, rx, ry, rz, q1)
        _keep(W, _S + 14, l, p2x, p2y, p2z, q2)
        _keep(W, _S + 28, l, p3x, p3y, p3z, q3)
        _keep(W, _S + 42, l, p4x, p4y, p4z, q4)
        go = W[_ACT * LANES + l] != 0.0  # (selects, not branches: the lanes' loop stays one vector loop)
        W[0 * LANES + l] = rx + hk6 * ((vx + 2 * (v2x + v3x)) + v4x) if go else rx
        W[1 * LANES + l] = ry + hk6 * ((vy + 2 * (v2y + v3y)) + v4y) if go else ry
        W[2 * LANES + l] = rz + hk6 * ((vz + 2 * (v2z + v3z)) + v4z) if go else rz
        W[3 * LANES + l] = vx + hk6 * ((a1x + 2 * (a2x + a3x)) + a4x) if go else vx
        W[4 * LANES + l] = vy + hk6 * ((a1y + 2 * (a2y + a3y)) + a4y) if go else vy
        W[5 * LANES + l] = vz + hk6 * ((a1z + 2 * (a2z + a3z)) + a4z) if go else vz


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _keep(W, o, l, px, py, pz, q):
    """Stage position ``(px, py, pz)`` and real intermediates ``q`` of lane ``l`` into rows ``o`` on."""
    W[o * LANES + l], W[(o + 1) * LANES + l], W[(o + 2) * LANES + l] = px, py, pz
    W[(o + 3) * LANES + l], W[(o + 4) * LANES + l], W[(o + 5) * LANES + l], W[(o + 6) * LANES + l], W[(o + 7) * LANES + l], W[(o + 8) * LANES + l] = q[0], q[1], q[2], q[3], q[4], q[5]
    W[(o + 9) * LANES + l], W[(o + 10) * LANES + l], W[(o + 11) * LANES + l], W[(o + 12) * LANES + l], W[(o + 13) * LANES + l] = q[6], q[7], q[8], q[9], q[10]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _q(W, o, l):
    """Stage ``o``'s real intermediates of lane ``l`` as :func:`_acc_re` returns them."""
    return (W[(o + 3) * LANES + l], W[(o + 4) * LANES + l], W[(o + 5) * LANES + l], W[(o + 6) * LANES + l], W[(o + 7) * LANES + l], W[(o + 8) * LANES + l], W[(o + 9) * LANES + l],
            W[(o + 10) * LANES + l], W[(o + 11) * LANES + l], W[(o + 12) * LANES + l], W[(o + 13) * LANES + l])


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _imaginary_stages(W, c, c_j2):
    """The RK4 step's imaginary parts of copy ``c`` for every lane (:func:`_rk4`'s, term for term)."""
    nl = W.shape[0] // _ROWS  # = LANES, known only when run: a loop of a known 8 would be unrolled to scalars
    i0 = _I + 6 * c
    for l in range(nl):
        hk = W[_HS * LANES + l]
        hk2, hk6 = hk / 2, hk / 6
        rxi, ryi, rzi, vxi, vyi, vzi = W[i0 * LANES + l], W[(i0 + 1) * LANES + l], W[(i0 + 2) * LANES + l], W[(i0 + 3) * LANES + l], W[(i0 + 4) * LANES + l], W[(i0 + 5) * LANES + l]
        o1, o2, o3, o4 = _S, _S + 14, _S + 28, _S + 42
        b1x, b1y, b1z = _acc_im(W[o1 * LANES + l], W[(o1 + 1) * LANES + l], W[(o1 + 2) * LANES + l], rxi, ryi, rzi, _q(W, o1, l), c_j2)
        w2x, w2y, w2z = vxi + hk2 * b1x, vyi + hk2 * b1y, vzi + hk2 * b1z
        b2x, b2y, b2z = _acc_im(W[o2 * LANES + l], W[(o2 + 1) * LANES + l], W[(o2 + 2) * LANES + l], rxi + hk2 * vxi, ryi + hk2 * vyi,
                                rzi + hk2 * vzi, _q(W, o2, l), c_j2)
        w3x, w3y, w3z = vxi + hk2 * b2x, vyi + hk2 * b2y, vzi + hk2 * b2z
        b3x, b3y, b3z = _acc_im(W[o3 * LANES + l], W[(o3 + 1) * LANES + l], W[(o3 + 2) * LANES + l], rxi + hk2 * w2x, ryi + hk2 * w2y,
                                rzi + hk2 * w2z, _q(W, o3, l), c_j2)
        w4x, w4y, w4z = vxi + hk * b3x, vyi + hk * b3y, vzi + hk * b3z
        b4x, b4y, b4z = _acc_im(W[o4 * LANES + l], W[(o4 + 1) * LANES + l], W[(o4 + 2) * LANES + l], rxi + hk * w3x, ryi + hk * w3y,
                                rzi + hk * w3z, _q(W, o4, l), c_j2)
        W[i0 * LANES + l] = rxi + hk6 * ((vxi + 2 * (w2x + w3x)) + w4x)
        W[(i0 + 1) * LANES + l] = ryi + hk6 * ((vyi + 2 * (w2y + w3y)) + w4y)
        W[(i0 + 2) * LANES + l] = rzi + hk6 * ((vzi + 2 * (w2z + w3z)) + w4z)
        W[(i0 + 3) * LANES + l] = vxi + hk6 * ((b1x + 2 * (b2x + b3x)) + b4x)
        W[(i0 + 4) * LANES + l] = vyi + hk6 * ((b1y + 2 * (b2y + b3y)) + b4y)
        W[(i0 + 5) * LANES + l] = vzi + hk6 * ((b1z + 2 * (b2z + b3z)) + b4z)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _moments(W, hstep):
    """``Φ`` (copy ``b``'s imaginary part of component ``a`` over ``h``), ``B = Φ P``, ``A = B Φᵀ + Q`` (each entry
    the chain ``s ← fma(x_j, y_j, s)``, ``j = 0..5``, from ``s = 0``: :func:`~.orbit3d_replay._row_product`'s) and
    ``P ← (A + Aᵀ)/2`` in the lanes that step; a lane whose mean or ``Φ`` is not finite is marked and steps no more."""
    nl = W.shape[0] // _ROWS  # = LANES, known only when run: a loop of a known 8 would be unrolled to scalars
    for l in range(nl):
        z = 0.0
        for a in range(6):
            z += W[a * LANES + l] * 0.0
            for b in range(6):
                f = W[(_I + 6 * b + a) * LANES + l] / hstep
                W[(_F + 6 * a + b) * LANES + l] = f
                z += f * 0.0
        W[_BAD * LANES + l] = 1.0 if z != 0.0 and W[_ACT * LANES + l] != 0.0 else W[_BAD * LANES + l]
    for a in range(6):
        for b in range(6):
            for l in range(nl):
                s = 0.0
                for j in range(6):
                    s = _fma(W[(_F + 6 * a + j) * LANES + l], W[(_C + 6 * j + b) * LANES + l], s)
                W[(_B + 6 * a + b) * LANES + l] = s
    for a in range(6):
        for b in range(6):
            for l in range(nl):
                s = 0.0
                for j in range(6):
                    s = _fma(W[(_B + 6 * a + j) * LANES + l], W[(_F + 6 * b + j) * LANES + l], s)
                W[(_A + 6 * a + b) * LANES + l] = s
    for l in range(nl):
        for a in range(3):
            W[(_A + 7 * a) * LANES + l] += W[_H3 * LANES + l]
            W[(_A + 6 * a + a + 3) * LANES + l] += W[_H2 * LANES + l]
            W[(_A + 6 * (a + 3) + a) * LANES + l] += W[_H2 * LANES + l]
            W[(_A + 7 * (a + 3)) * LANES + l] += W[_H1 * LANES + l]
    for l in range(nl):
        go = W[_ACT * LANES + l] != 0.0
        for a in range(6):
            for b in range(6):
                W[(_C + 6 * a + b) * LANES + l] = 0.5 * (W[(_A + 6 * a + b) * LANES + l] + W[(_A + 6 * b + a) * LANES + l]) if go else W[(_C + 6 * a + b) * LANES + l]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def replay_lanes(X, P, h, k, order, max_step, q, mu, c_j2, hstep):
    """:func:`_replay`'s ``(x, P, bad)`` with the rows taken ``LANES`` at a time in ``order`` (the
    rows of ``k > 0``, by substeps per step and then longest ``k`` first; a group's rows share one number of RK4
    substeps per step: the group ends where it changes), a group whose lanes would mostly idle (``LANE_GROUP_COST``)
    track by track. ``bad``: the first row (in row order) whose prediction is not finite, −1 for none."""
    n = order.shape[0]
    xo, Po = X.copy(), P.copy()
    W = np.zeros(_ROWS * LANES)  # row r, lane l at r·LANES + l (a constant stride: the lanes' loops vectorise)
    rows = np.empty(LANES, np.int64)
    bad = -1
    g = 0
    while g < n:
        m = int(math.ceil(abs(h[order[g]]) / max_step))
        cnt, kmax = 0, 0
        while cnt < LANES and g + cnt < n and int(math.ceil(abs(h[order[g + cnt]]) / max_step)) == m:
            rows[cnt] = order[g + cnt]
            cnt += 1
        for l in range(LANES):
            i = rows[l] if l < cnt else rows[0]  # an idle lane repeats the first track, taking no step
            hi = h[i]
            W[_HS * LANES + l] = hi / max(m, 1)
            W[_H3 * LANES + l], W[_H2 * LANES + l] = q * (hi ** 3.0 / 3), q * (hi ** 2.0 / 2)
            W[_H1 * LANES + l] = q * hi
            W[_K * LANES + l] = k[i] if l < cnt else 0.0
            W[_BAD * LANES + l] = 0.0
            kmax = max(kmax, k[i])
            for a in range(6):
                W[(_R + a) * LANES + l] = X[i, a]
                for b in range(6):
                    W[(_C + 6 * a + b) * LANES + l] = P[i, a, b]
        sumk = 0
        for l in range(cnt):
            sumk += k[rows[l]]
        if sumk < LANE_GROUP_COST * kmax:  # too few lanes busy: track by track
            for l in range(cnt):
                i = rows[l]
                if _replay_row(xo, Po, i, h[i], k[i], max_step, q, mu, c_j2, hstep) and (bad < 0 or i < bad):
                    bad = i
            g += cnt
            continue
        for step in range(kmax):
            for l in range(LANES):
                W[_ACT * LANES + l] = 1.0 if step < W[_K * LANES + l] and W[_BAD * LANES + l] == 0.0 else 0.0
                for a in range(6):
                    for c in range(6):
                        W[(_I + 6 * c + a) * LANES + l] = hstep if a == c else 0.0
            for _s in range(m):
                _real_stages(W, mu, c_j2)
                # (the copies by constants: their rows' offsets known when compiled)
                _imaginary_stages(W, 0, c_j2)
                _imaginary_stages(W, 1, c_j2)
                _imaginary_stages(W, 2, c_j2)
                _imaginary_stages(W, 3, c_j2)
                _imaginary_stages(W, 4, c_j2)
                _imaginary_stages(W, 5, c_j2)
            _moments(W, hstep)
        for l in range(cnt):
            i = rows[l]
            if W[_BAD * LANES + l] != 0.0 and (bad < 0 or i < bad):
                bad = i
            for a in range(6):
                xo[i, a] = W[(_R + a) * LANES + l]
                for b in range(6):
                    Po[i, a, b] = W[(_C + 6 * a + b) * LANES + l]
        g += cnt
    return xo, Po, bad


def replay_j2(model, x, P, h, k):
    """EKF prediction of ``(x, P)`` (``(n, 6)``, ``(n, 6, 6)``) through :class:`~.orbit3d.J2Orbit3D` ``model``, row
    ``i`` in ``k[i]`` (≥ 0) steps of ``h[i]`` (≥ 0) s each: ``(x, P)``. Raises ``ValueError`` as
    :meth:`~.orbit3d.J2Orbit3D.transition` does for a state propagating to a non-finite one."""
    from .orbit import _H_STEP

    X = np.ascontiguousarray(x, dtype=float)
    if not np.all(np.isfinite(X)):
        check_finite_array(X, "x")  # raises, naming x
    if len(X) == 0:
        return X.copy(), np.array(P, dtype=float)
    h, k = np.ascontiguousarray(h, dtype=float), np.ascontiguousarray(k, dtype=np.int64)
    # the tracks side by side (:func:`replay_lanes`), grouped by RK4 substeps per step, then longest first
    steps = np.flatnonzero(k > 0)
    order = steps[np.lexsort((-k[steps], np.ceil(np.abs(h[steps]) / float(model.max_step))))]
    xo, Po, bad = replay_lanes(X, np.ascontiguousarray(P, dtype=float), h, k, order, float(model.max_step),
                               float(model.q), float(model.mu), float(1.5 * model.j2 * model.mu * model.radius**2),
                               _H_STEP)
    if bad >= 0:
        r = float(np.linalg.norm(X[bad, :3]))
        raise ValueError(f"x: state {bad} (position radius {r:.6g} km) propagates to a non-finite state: it is at or "
                         "falls through the Earth's centre, where the two-body + J2 acceleration is singular")
    return xo, Po


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _fma_products(ar, ai, br, bi, F, P):
    """The imaginary parts of ``(ar + i ai)(br + i bi)`` and the products ``F P`` as the kernel rounds them."""
    im = np.empty(len(ar))
    for i in range(len(ar)):
        im[i] = _fma(ar[i], bi[i], ai[i] * br[i])
    out = np.empty_like(F)
    for n in range(F.shape[0]):
        for a in range(6):
            for b in range(6):
                s = 0.0
                for j in range(6):
                    s = _fma(F[n, a, j], P[n, j, b], s)
                out[n, a, b] = s
    return im, out


def rounds_as_numpy() -> bool:
    """Whether this machine's numpy complex product and stacked 6 × 6 matrix product round as the kernel does
    (module docstring), so that :func:`replay_j2` is bit for bit the array passes: checked on seeded random numbers."""
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(2, 4096)) + 1j * rng.normal(size=(2, 4096))
    F, P = rng.normal(size=(2, 256, 6, 6))
    im, FP = _fma_products(a.real.copy(), a.imag.copy(), b.real.copy(), b.imag.copy(), F, P)
    return bool(np.array_equal(im, (a * b).imag) and np.array_equal(FP, F @ P))
