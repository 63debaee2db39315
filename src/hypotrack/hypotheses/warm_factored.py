"""The factored δ-GLMB engine's compiled kernels on the catalogue's radar path, loaded (or compiled) now.

numba loads a ``cache=True`` kernel from its on-disk cache on the kernel's first call in a process (~1–10 ms a
kernel, ~70 ms for the set below), or compiles it when the cache is cold (seconds). In a timed loop that first call
falls in a scan: the whole set in the first scan of :func:`~hypotrack.experiments.ssa_catalogue.run.run_tracker`
(which times every scan), the birth band test (:mod:`.factored.births_kernels`, first called when the first birth
terms exist) in the scale harness's first timed scan. :func:`warm_engine` compiles each kernel for the argument
types the engine passes it (:data:`ENGINE_KERNELS`), which is a load from the cache when one is there — the same
machine code the first call would have loaded; a test runs a catalogue tracker after it and checks that no kernel
gains a signature inside its scans.
"""

from __future__ import annotations

from numba import types as nt

from ..association import clustering
from ..models import measurement, orbit3d, orbit3d_replay, plausibility
from ..scenarios.catalogue import admissible_kernels, fov_kernels, radar_kernels
from .factored import births_kernels, lane_kernels, scorable_kernels

__all__ = ["ENGINE_KERNELS", "warm_engine"]

_F, _I, _B = nt.float64, nt.int64, nt.boolean
_f1, _f2, _f3, _f2a = _F[::1], _F[:, ::1], _F[:, :, ::1], _F[:, :]
_i1, _i2, _i3, _b1 = _I[::1], _I[:, ::1], _I[:, :, ::1], _B[::1]

#: ``(module, kernel name, argument types)`` of every kernel a factored catalogue step calls, with the types its
#: call site builds (C-contiguous float64/int64/bool arrays; the near-field test's states may be a strided view)
ENGINE_KERNELS = (
    (births_kernels, "_band", (_f2, _i1, _i1, _i1, _f2, _f2, _b1)),
    (scorable_kernels, "_certify", (_f3, _F)),
    (lane_kernels, "rebuild", (_i1, _f2, _B, _f1, _i1, _f1, _f1, _f1, _i1, _b1, _i1, _i1, _f2, _f3, _f1, _f1, _f2,
                               _f3, _i1, _f1, _f1, _F, _F, _B, _B, _f2, _f3, _I, _i1, _f2, _f1, _i1, _f1, _f1)),
    (measurement, "_pair_distances", (_f2, _f2, _f3, _b1)),
    (orbit3d, "_rk4_j2_rows", (_f2, _F, _I, _F, _F)),
    (orbit3d_replay, "replay_lanes", (_f2, _f3, _f1, _i1, _i1, _F, _F, _F, _F, _F)),
    (plausibility, "_energy_perigee_columns", (_f2, _F, _F)),
    (admissible_kernels, "_components", (_f2, _f1, _f2, _f2, _F, _F, _F, _F, _F, _I, _I, _F)),
    (fov_kernels, "_decide", (_f2, _b1, _F, _F, _F, _F, _F, _F, _B, _F)),
    (radar_kernels, "_batch", (_f2, _f3, _f2, _f1, _f1, _f2, _f1, _f2, _F, _B, _I)),
    (radar_kernels, "_jacobians", (_f2, _f1, _f1, _f2)),
    (radar_kernels, "_near", (_f2a, _f2, _f1, _f2, _F, _B)),
    (radar_kernels, "_update_known", (_f2, _f3, _f2, _i2, _i3, _i2, _i3, _f1, _i1, _f2, _f3, _f3, _f3, _f1, _f1,
                                      _f2, _f1, _f2, _F, _B)),
    (clustering, "_union_find", (_I, _i1, _i1)),
)


def warm_engine() -> None:
    """Compile (load from numba's cache, when there) each kernel of :data:`ENGINE_KERNELS` for its argument types,
    before a timed loop steps a factored tracker; a kernel already compiled for them is left as it is."""
    for module, name, args in ENGINE_KERNELS:
        getattr(module, name).compile(args)
