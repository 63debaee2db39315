"""The theory notebooks (theory/*.py): each runs as a script, passes its own checks, writes its
findings, fails when one of its paper formulas is broken, and executes as a rendered notebook.

The notebooks assert the mathematics themselves; these tests check that they really ran (exit
status, the JSON they wrote, the numbers in it against independent computations) and that their
checks are sensitive (a formula perturbed by one count or 0.1 % makes a named check fail).
"""

from __future__ import annotations

import importlib.util
import json
import math
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from math import comb, factorial
from pathlib import Path

import pytest
from scipy.stats import binom, poisson

ROOT = Path(__file__).resolve().parents[3]
THEORY = ROOT / "theory"
NOTEBOOKS = ["hypothesis_count", "likelihood_normalisation", "birth_poisson_limit", "set_integrals",
             "ideal_filter_mospa"]
FIGURES = {
    "hypothesis_count": ["growth"],
    "likelihood_normalisation": ["eq9"],
    "birth_poisson_limit": ["tv_distance", "eq43"],
    "set_integrals": [],
    "ideal_filter_mospa": [],
}


def run_notebook(name, out_dir, *, perturb=None, extra_args=()):
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("HYPOTRACK_THEORY_PERTURB", None)
    env["HYPOTRACK_THEORY_OUT"] = str(out_dir)
    if perturb is not None:
        env["HYPOTRACK_THEORY_PERTURB"] = perturb
    return subprocess.run([sys.executable, str(THEORY / f"{name}.py"), *extra_args], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)


# One formula per notebook, and the check that must then fail first.
PERTURBATIONS = [
    ("hypothesis_count", "eq4_count", "Eq. 4 equals brute-force enumeration"),
    ("likelihood_normalisation", "eq8_prior", "Eq. 9: sum_j p_ij = 1 exactly"),
    ("birth_poisson_limit", "binomial_birth_probability", "Eq. 32: the direct series of the binomial pmf"),
    ("set_integrals", "poisson_rfs_density", "Poisson RFS: the n-point term of the set integral"),
    ("ideal_filter_mospa", "negative_part_formula", "polar integral = rho/2 - (sqrt(1 - rho^2) + rho arcsin rho)/pi"),
    ("ideal_filter_mospa", "riccati_map", "fixed point of the Riccati map is a root"),
]


@pytest.fixture(scope="module")
def notebook_runs(tmp_path_factory):
    """Every notebook as a plain script, as it is and with each formula of PERTURBATIONS broken:
    {(name, perturbed formula or None): (process result, output folder)}.

    The runs are independent processes (each with its own output folder), so they run as many at
    a time as there are cores instead of one after another.
    """
    runs = [(name, None) for name in NOTEBOOKS] + [(name, formula) for name, formula, _ in PERTURBATIONS]

    def run(key):
        name, formula = key
        out = tmp_path_factory.mktemp(name if formula is None else f"{name}-{formula}")
        return key, (run_notebook(name, out, perturb=formula), out)

    with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
        return dict(pool.map(run, runs))


@pytest.fixture(scope="module")
def executed(notebook_runs):
    """Every notebook run once as a plain script: its process result, findings and output folder."""
    results = {}
    for name in NOTEBOOKS:
        proc, out = notebook_runs[name, None]
        findings = json.loads((out / f"{name}.json").read_text()) if (out / f"{name}.json").exists() else None
        results[name] = (proc, findings, out)
    return results


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_notebook_runs_as_script_and_passes_its_checks(executed, name):
    proc, findings, out = executed[name]
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert findings is not None and findings["notebook"] == name
    assert findings["all_passed"] and findings["n_checks"] == len(findings["checks"]) >= 10
    # Every check the JSON lists was printed as passed, and nothing failed.
    assert proc.stdout.count("[PASS]") == findings["n_checks"]
    assert "[FAIL]" not in proc.stdout
    for stem in FIGURES[name]:
        for ext in ("pdf", "png"):
            assert (out / f"{name}_{stem}.{ext}").stat().st_size > 10_000
    assert findings["claims"], "each notebook contributes rows to the reproduction ledger"


def test_hypothesis_count_values(executed):
    _, findings, _ = executed["hypothesis_count"]
    values = findings["values"]
    assert values["A_10_5"] == 63591
    assert sum(values["A_10_5_terms"]) == 63591
    table = values["brute_force_table_M_rows_m_columns"]
    assert all(table[M][m] == sum(comb(M, n) * comb(m, n) * factorial(n) for n in range(min(M, m) + 1))
               for M in range(7) for m in range(7))
    growth = {row["n"]: row for row in values["growth_table"]}
    # Exact integers beyond 2**53 are stored as strings.
    a70 = int(growth[70]["A_exact"])
    assert a70 == sum(comb(70, n) ** 2 * factorial(n) for n in range(71))
    assert len(str(a70)) == growth[70]["digits"] == 107
    assert values["first_n_with_A_nn_at_least_1e8_1e33_1e100"] == {"8": 10, "33": 28, "100": 67}


def test_likelihood_normalisation_values(executed):
    _, findings, _ = executed["likelihood_normalisation"]
    values = findings["values"]
    assert values["eq9_sum_M10_m5_pD095"] == pytest.approx(binom.cdf(5, 10, 0.95), rel=1e-12)
    assert values["eq20_integral"]["M=2,m=2"] == "1"
    statuses = {c["item"]: c["status"] for c in findings["claims"]}
    assert statuses["Eq. 9: children's prior probabilities sum to 1"] == "not reproduced"
    assert statuses["Eq. 39: the two-target likelihood integrates to 1"] == "reproduced"


def test_birth_poisson_limit_values(executed):
    _, findings, _ = executed["birth_poisson_limit"]
    rows = findings["values"]["tv_table"]
    for rate in (0.5, 2.0, 10.0):
        largest = max((r for r in rows if r["lambdaV"] == rate), key=lambda r: r["M"])
        # Independent of the notebook: the TV distance at M = 1e7 from scipy directly.
        M = largest["M"]
        k = range(int(rate * 10 + 60))
        tv = 0.5 * sum(abs(binom.pmf(i, M, rate / M) - poisson.pmf(i, rate)) for i in k)
        assert largest["tv"] == pytest.approx(tv, rel=1e-6)
    assert findings["values"]["eq43_variance_matched_counterexample"]["ratio_over_1_minus_pD"] > 1


def test_ideal_filter_mospa_values(executed):
    _, findings, _ = executed["ideal_filter_mospa"]
    values = findings["values"]
    # Independent of the notebook: iterate the scalar Riccati map to its fixed point.
    A, r = math.exp(-0.005), 0.1
    Q, P = 1.0 * (1 - A * A), 1.0
    for _ in range(2000):
        P = A * A * P * r / (P + r) + Q
    assert values["steady_prediction_variance"] == pytest.approx(P, rel=1e-12)
    assert abs(values["steady_prediction_variance"] - 0.0363) < 5e-5
    assert max(values["best_pairing_mospa_by_initial_variance"].values()) < 0.0363 - 5e-5
    assert abs(values["labelled_after_transient"] - 0.0363) <= 5e-5


@pytest.mark.parametrize("name,formula_name,failing_check", PERTURBATIONS)
def test_breaking_a_formula_makes_the_notebook_fail(notebook_runs, name, formula_name, failing_check):
    proc, out = notebook_runs[name, formula_name]
    assert proc.returncode != 0
    assert f"check failed: {failing_check}" in proc.stderr
    assert not (out / f"{name}.json").exists(), "a failed notebook must not write findings"


@pytest.fixture()
def common(monkeypatch):
    """theory/_common.py imported under its own name (it is not a package module)."""
    monkeypatch.delenv("HYPOTRACK_THEORY_PERTURB", raising=False)
    spec = importlib.util.spec_from_file_location("theory_common_under_test", THEORY / "_common.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_formula_perturbation_mechanism(common, monkeypatch, tmp_path):
    import sympy as sp

    monkeypatch.setenv("HYPOTRACK_THEORY_PERTURB", "count, ratio")

    @common.formula
    def count(n):
        return n * (n - 1) // 2

    @common.formula
    def ratio(x):
        return sp.Rational(1, 2) * x

    @common.formula
    def untouched(x):
        return x

    assert count(5) == 11 and ratio(2) == sp.Rational(1001, 1000) and untouched(3) == 3
    findings = common.Findings("demo", "test")
    findings.out = tmp_path
    assert findings.write().exists()  # every requested perturbation was defined


def test_perturbing_an_unknown_formula_is_an_error_not_a_detection(common, monkeypatch, tmp_path):
    monkeypatch.setenv("HYPOTRACK_THEORY_PERTURB", "no_such_formula")
    findings = common.Findings("demo", "test")
    findings.out = tmp_path
    findings.check("a true statement", True)
    with pytest.raises(KeyError, match="no_such_formula"):
        findings.write()
    assert not (tmp_path / "demo.json").exists()


def test_check_raises_and_output_directory(common, monkeypatch, tmp_path):
    monkeypatch.setenv("HYPOTRACK_THEORY_OUT", str(tmp_path / "from_env"))
    assert common.output_dir([]) == tmp_path / "from_env"
    assert common.output_dir(["--out", str(tmp_path / "from_arg")]) == tmp_path / "from_arg"
    assert (tmp_path / "from_arg").is_dir()
    with pytest.raises(ValueError, match="--out"):
        common.output_dir(["--out"])
    findings = common.Findings("demo", "test")
    with pytest.raises(AssertionError, match="check failed: two is three"):
        findings.check("two is three", 2 == 3)
    with pytest.raises(ValueError, match="status"):
        findings.claim("item", "source", 1, 2, "roughly")


def test_notebook_figures_are_held_to_the_report_legibility_rules(common, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    findings = common.Findings("demo", "test")
    findings.out = tmp_path
    # 8 pt on a 13-in figure prints at 8 × 6.535 / 13 = 4.0 pt on the report's line
    fig, ax = plt.subplots(figsize=(13, 4))
    ax.set_xlabel("x", fontsize=8)
    with pytest.raises(ValueError, match="4.0 pt"):
        findings.figure(fig, "too_wide")
    assert not list(tmp_path.glob("demo_too_wide.*"))
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6.5, 3))
    ax.set_xlabel("x", fontsize=8)
    fig.tight_layout()
    assert [p.name for p in findings.figure(fig, "fits")] == ["demo_fits.pdf", "demo_fits.png"]
    assert (tmp_path / "demo_fits.pdf").exists()
    plt.close(fig)


def test_brute_force_enumerator_and_json_encoding(common):
    import sympy as sp

    events = list(common.association_events(3, 2))
    assert len(events) == len(set(events)) == 13  # A(3, 2) = 1 + 6 + 6
    assert all(len({j for j in e if j >= 0}) == sum(j >= 0 for j in e) for e in events)
    assert list(common.association_events(0, 0)) == [()]
    assert common._jsonable(2**60) == str(2**60) and common._jsonable(7) == 7
    assert common._jsonable(sp.Rational(1, 3)) == "1/3" and common._jsonable(sp.Integer(5)) == 5
    x, y = sp.symbols("x y", real=True)
    gx, gy = (sp.exp(-v**2 / 2) / sp.sqrt(2 * sp.pi) for v in (x, y))
    # 3 * 1 + E[y^2] = 4 over the plane; half the mass on [0, oo).
    assert common.integrate_sum_of_products(3 * gx * gy + gx * gy * y**2, [x, y]) == 4
    assert common.integrate_sum_of_products(gx, [x], 0, sp.oo) == sp.Rational(1, 2)


MINI_NOTEBOOK = """# ---
# jupyter:
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# A miniature theory notebook: the same imports, checks, figure and JSON as the real ones.

# %%
import matplotlib.pyplot as plt
import sympy as sp

from _common import Findings
from hypotrack.association import count_associations

findings = Findings("mini", "test")
findings.check("A(10, 5) = 63591", count_associations(10, 5) == 63591)
findings.check("sympy integrates a Gaussian", sp.integrate(sp.exp(-sp.Symbol("x") ** 2), (sp.Symbol("x"), -sp.oo, sp.oo))
               == sp.sqrt(sp.pi))
fig, ax = plt.subplots()
ax.plot([0, 1], [0, 1])
findings.figure(fig, "line")
plt.show()

# %%
findings.write()
"""


def test_notebook_executes_with_the_native_kernel(tmp_path):
    """The pipeline's path (workflows/rules/theory.smk): jupytext -> ipynb, nbconvert --execute
    with ipykernel's python3 kernel (cwd is the notebook's folder, _common found through
    PYTHONPATH, output directory through HYPOTRACK_THEORY_OUT), then HTML."""
    source = tmp_path / "src" / "mini.py"
    source.parent.mkdir()
    source.write_text(MINI_NOTEBOOK)
    out = tmp_path / "out"
    out.mkdir()  # Snakemake creates the output folder before the rule runs
    ipynb = out / "mini.ipynb"
    env = dict(os.environ, HYPOTRACK_THEORY_OUT=str(out),
               PYTHONPATH=os.pathsep.join(filter(None, [str(THEORY), os.environ.get("PYTHONPATH")])))
    env.pop("HYPOTRACK_THEORY_PERTURB", None)
    env.pop("MPLBACKEND", None)
    for cmd in (
        ["-m", "jupytext", "--to", "ipynb", "--output", str(ipynb), str(source)],
        ["-m", "nbconvert", "--to", "notebook", "--execute", "--inplace",
         "--ExecutePreprocessor.kernel_name=python3", "--ExecutePreprocessor.timeout=300", str(ipynb)],
        ["-m", "nbconvert", "--to", "html", str(ipynb)],
    ):
        proc = subprocess.run([sys.executable, *cmd], cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0, proc.stderr[-3000:]
    nb = json.loads(ipynb.read_text())
    outputs = [o for c in nb["cells"] if c["cell_type"] == "code" for o in c.get("outputs", [])]
    printed = "".join("".join(o.get("text", "")) for o in outputs)
    assert printed.count("[PASS]") == 2
    assert any("image/png" in o.get("data", {}) for o in outputs), "the figure is rendered inline"
    assert (out / "mini.html").stat().st_size > 10_000
    assert (out / "mini_line.png").exists() and (out / "mini_line.pdf").exists()
    assert json.loads((out / "mini.json").read_text())["all_passed"]


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_every_verdict_names_a_broken_formula_that_fails(executed, name):
    """Every reproduced or qualitative row runs its check on a formula with a known defect (the count
    without false alarms, a likelihood without its normalising factor, ...), and that control fails."""
    from hypotrack.reporting.verdict import parse_control

    _, findings, _ = executed[name]
    for claim in findings["claims"]:
        if claim["status"] in ("reproduced", "qualitative"):
            what, value, passes = parse_control(claim["control"])
            assert what and value and not passes, claim["item"]
