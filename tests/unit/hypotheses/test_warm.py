"""``warm_samplers`` loads the samplers' and JPDA's entry kernels in a fresh process (what a timed loop relies on)."""

import subprocess
import sys

CODE = """
from numba.core.registry import CPUDispatcher
import hypotrack.association.samplers.chain as c, hypotrack.association.samplers.events as e
import hypotrack.association.samplers.gibbs as g
import hypotrack.association.lbp as lbp, hypotrack.association.marginals as jm
from hypotrack.hypotheses.warm import warm_samplers
entry = {"gibbs._sweeps": g._sweeps, "events.gather_sum": e.gather_sum, "chain._run_chain": c._run_chain,
         "chain._completion_round": c._completion_round, "marginals._marginals": jm._marginals,
         "lbp._iterate": lbp._iterate}
assert all(isinstance(k, CPUDispatcher) for k in entry.values())
before = {n: len(k.signatures) for n, k in entry.items()}
warm_samplers()
print(sorted(n for n, k in entry.items() if before[n] == 0 and len(k.signatures) == 1))
"""


def test_a_fresh_process_has_each_samplers_entry_kernel_compiled_once_after_it():
    out = subprocess.run([sys.executable, "-c", CODE], capture_output=True, text=True, check=True).stdout.split("\n")
    assert out[-2] == str(sorted(["gibbs._sweeps", "events.gather_sum", "chain._run_chain", "chain._completion_round",
                                  "marginals._marginals", "lbp._iterate"]))
