"""``warm_engine`` compiles the factored engine's catalogue kernels for the types the engine passes them: in a fresh
process each kernel has one signature after it, and a δ-GLMB catalogue run after it adds none inside its scans (no
kernel first loaded from numba's cache, or compiled, in a timed scan)."""

import subprocess
import sys

FRESH = """
from numba.core.registry import CPUDispatcher
from hypotrack.hypotheses.warm import warm_engine
from hypotrack.hypotheses.warm_factored import ENGINE_KERNELS
kernels = {f"{m.__name__}.{n}": getattr(m, n) for m, n, _ in ENGINE_KERNELS}
assert all(isinstance(k, CPUDispatcher) for k in kernels.values())
before = {n: len(k.signatures) for n, k in kernels.items()}
warm_engine()
print(sorted(n for n, k in kernels.items() if before[n] == 0 and len(k.signatures) == 1))
warm_engine()  # a second call compiles nothing more
print(sorted(n for n, k in kernels.items() if len(k.signatures) != 1))
"""

RUN = """
import importlib, pkgutil, yaml
import hypotrack
from numba.core.registry import CPUDispatcher
from hypotrack.experiments.ssa_catalogue import scale
import hypotrack.hypotheses.factored.engine as eng
mods = [importlib.import_module(m.name) for m in pkgutil.walk_packages(hypotrack.__path__, "hypotrack.")
        if ".workflows" not in m.name]
every = {f"{m.__name__}.{n}": v for m in mods for n, v in vars(m).items()
         if isinstance(v, CPUDispatcher) and v.__module__ == m.__name__}
sigs = lambda: {n: len(d.signatures) for n, d in every.items()}
gained, first = set(), []
step = eng.FactoredFilter.step
def counted(self, *a, **kw):
    s0 = sigs()
    out = step(self, *a, **kw)
    gained.update(n for n, c in sigs().items() if c > s0[n])
    return out
eng.FactoredFilter.step = counted
cfg = yaml.safe_load(open("workflows/config/default.yaml"))["ssa_catalogue"]
cfg["scale"]["n_scans"] = 8
r = scale.measure_run(cfg, "glmb", 1500, 3)
from hypotrack.hypotheses.warm_factored import ENGINE_KERNELS
used = {f"{m.__name__}.{n}" for m, n, _ in ENGINE_KERNELS}
print(sorted(gained))
print(r["returns_per_scan"] > 0, all(len(every[n].signatures) == 1 for n in used))
"""


def test_a_fresh_process_has_each_engine_kernel_compiled_once_after_it():
    out = subprocess.run([sys.executable, "-c", FRESH], capture_output=True, text=True, check=True).stdout.split("\n")
    from hypotrack.hypotheses.warm_factored import ENGINE_KERNELS

    assert out[-3] == str(sorted(f"{m.__name__}.{n}" for m, n, _ in ENGINE_KERNELS))
    assert out[-2] == "[]"


def test_a_catalogue_glmb_run_after_it_compiles_no_kernel_inside_its_scans():
    out = subprocess.run([sys.executable, "-c", RUN], capture_output=True, text=True, check=True).stdout.split("\n")
    assert out[-3] == "[]"  # no kernel of the package gained a signature inside a scan
    assert out[-2] == "True True"  # the run saw returns; every warmed kernel kept the one signature warmed
