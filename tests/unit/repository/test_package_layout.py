"""The package's layout: one package per experiment, no import circle.

The experiments mirror ``workflows/rules/<experiment>.smk`` (a reader looking for where a figure or
verdict is made finds its package by the rule's name), and the import graph of ``hypotrack`` is a
directed acyclic graph, so every module can be read (and tested) after the modules it uses. An
experiment package uses another only through the shared modules of ``experiments/`` (seeds and
shards, timing and steppers) or by one of the documented pairs of :data:`CROSS_IMPORTS`.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

ROOT = Path(__file__).resolve().parents[3]
PKG = ROOT / "src" / "hypotrack"
EXPERIMENTS = PKG / "experiments"
RULES = {p.stem for p in (ROOT / "workflows" / "rules").glob("*.smk")}
SHARED_MODULES = {"__init__", "seeds", "stepping"}  # the shared modules of the experiments (seeds; timing, steppers)
# Rules whose logic lives in another experiment's package or outside experiments/.
HOSTED = {"ssa15": "ssa", "ssa50": "ssa", "perf_hypotheses": "generation_time", "perf_interop": None,
          "theory": None, "paper": None}
#: The only imports from one experiment package (or one module of it) into another, with the reason; every
#: other experiment-to-experiment import goes through SHARED_MODULES. ssa hosts ssa50 and ssa15 (HOSTED).
CROSS_IMPORTS = {
    ("ssa_seeds", "ssa"): "the ssa50 and ssa15 verdicts over scenario seeds: ssa's scenario, trackers, evaluation "
                          "and claim ids, so a verdict over seeds is the single run's verdict repeated",
    ("ssa_catalogue.single_event", "ssa"): "document 000's single-event population measured on ssa50 itself: "
                                           "ssa50's R-FISST (ssa.trackers) and known catalogue (ssa.scenario)",
    ("ssa_breakup", "ssa_catalogue"): "the breakup cloud tracked as the catalogue is: the catalogue experiment's "
                                      "radar, motion model, tracking problem and trackers, and its scenario as the "
                                      "sparse control",
    ("ssa_catalogue.scorecard", "ssa_breakup"): "the catalogue scored as the breakup cloud is: the breakup "
                                                "experiment's scored run and operator's scorecard, one code for both",
}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def resolve(node: ast.ImportFrom, current: str, is_package: bool) -> str:
    if node.level == 0:
        return node.module or ""
    base = current.split(".")
    base = base if is_package else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def circles(edges: set[tuple[str, str]]) -> list[list[str]]:
    """The import circles of a graph: its strongly connected components of more than one module."""
    nodes = sorted({n for e in edges for n in e})
    index = {n: i for i, n in enumerate(nodes)}
    rows, cols = zip(*((index[a], index[b]) for a, b in edges)) if edges else ((), ())
    adjacency = coo_matrix(([1] * len(rows), (rows, cols)), shape=(len(nodes), len(nodes)))
    _, label = connected_components(adjacency, directed=True, connection="strong")
    groups = {}
    for n, lab in zip(nodes, label):
        groups.setdefault(lab, []).append(n)
    return [g for g in groups.values() if len(g) > 1]


def import_graph() -> set[tuple[str, str]]:
    """Every import (module level or inside a function) between hypotrack modules, as edges."""
    files = {module_name(p): p for p in PKG.rglob("*.py")}
    graph = set()
    for name, path in files.items():
        is_package = path.name == "__init__.py"
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            targets = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                mod = resolve(node, name, is_package)
                targets = [f"{mod}.{a.name}" if f"{mod}.{a.name}" in files else mod for a in node.names]
            for t in targets:
                while t and t not in files:  # hypotrack.x.y.Name -> the module that defines Name
                    t = t.rpartition(".")[0]
                if t and t != name and t.startswith("hypotrack"):
                    graph.add((name, t))
    return graph


def test_import_graph_has_no_circle():
    graph = import_graph()
    # A package's __init__ re-exporting its own submodules is not a circle of dependencies:
    # drop the edge from a submodule to its own package's __init__ when the __init__ imports it.
    graph = {(a, b) for a, b in graph if not (a.startswith(b + ".") and (b, a) in graph)}
    assert circles(graph) == [], f"import circles: {circles(graph)}"


def test_the_circle_check_sees_a_circle():
    graph = {("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")}
    assert [sorted(c) for c in circles(graph)] == [["a", "b", "c"]]
    assert circles({("a", "b"), ("b", "c")}) == []


# The ledger's modules: the claim schema and rules, its files, the LaTeX macros, the renderers, and the
# module that gathers them (hypotrack.reporting.ledger).
LEDGER = ("hypotrack.reporting.claims", "hypotrack.reporting.ledger_io", "hypotrack.reporting.macros",
          "hypotrack.reporting.renderers", "hypotrack.reporting.ledger")


def test_reporting_modules_import_each_other_one_way():
    graph = import_graph()
    assert ("hypotrack.reporting.readme", "hypotrack.reporting.claim_tables") in graph
    assert ("hypotrack.reporting.readme", "hypotrack.reporting.claims") in graph
    assert not [(a, b) for a, b in graph if a in LEDGER and b == "hypotrack.reporting.readme"]
    # within the ledger: the schema uses none of the others, and the facade is used by none of them
    assert not [b for a, b in graph if a == "hypotrack.reporting.claims" and b in LEDGER]
    assert not [a for a, b in graph if b == "hypotrack.reporting.ledger" and a.startswith("hypotrack.reporting")]


def test_reporting_never_imports_the_experiments():
    """Layering: the experiments use the reporting modules (ledger, macros, README), never the reverse,
    so a report or README block that needs an experiment's rendering reads a file the experiment wrote."""
    upward = sorted((a, b) for a, b in import_graph()
                    if a.startswith("hypotrack.reporting") and b.startswith("hypotrack.experiments"))
    assert upward == [], f"reporting modules importing experiments: {upward}"


def experiment_package(module: str) -> str | None:
    """``"ssa"`` for ``hypotrack.experiments.ssa.run``; None for a shared module or outside the experiments."""
    parts = module.split(".")
    if parts[:2] != ["hypotrack", "experiments"] or len(parts) < 3 or parts[2] in SHARED_MODULES:
        return None
    return parts[2]


def cross_experiment_imports(edges) -> list[tuple[str, str]]:
    """The edges from one experiment package into another that :data:`CROSS_IMPORTS` does not allow."""
    bad = []
    for a, b in sorted(edges):
        pa, pb = experiment_package(a), experiment_package(b)
        if pa is None or pb is None or pa == pb:
            continue
        within = ".".join(a.split(".")[2:4])  # package.module of the importer
        if (pa, pb) not in CROSS_IMPORTS and (within, pb) not in CROSS_IMPORTS:
            bad.append((a, b))
    return bad


def test_experiments_use_each_other_only_through_the_shared_modules():
    bad = cross_experiment_imports(import_graph())
    assert bad == [], ("imports from one experiment package into another (put the shared piece in a shared "
                       f"module of experiments/, a scenario in hypotrack.scenarios): {bad}")


def test_every_documented_cross_import_is_used():
    """An allowed pair that no module uses any more is dropped from the list (it only ever shrinks)."""
    used = set()
    for a, b in import_graph():
        pa, pb = experiment_package(a), experiment_package(b)
        if pa is not None and pb is not None and pa != pb:
            used |= {(pa, pb), (".".join(a.split(".")[2:4]), pb)}
    assert set(CROSS_IMPORTS) <= used, f"allowed but unused: {set(CROSS_IMPORTS) - used}"


def test_the_cross_import_check_sees_a_forbidden_import():
    edges = {("hypotrack.experiments.samplers.recorded", "hypotrack.experiments.glmb_benchmark.run"),
             ("hypotrack.experiments.samplers.run", "hypotrack.experiments.stepping"),
             ("hypotrack.experiments.ssa_seeds.run", "hypotrack.experiments.ssa"),
             ("hypotrack.experiments.ssa_catalogue.single_event", "hypotrack.experiments.ssa.trackers"),
             ("hypotrack.experiments.ssa_catalogue.run", "hypotrack.experiments.ssa.trackers"),
             ("hypotrack.experiments.perf_sht.run", "hypotrack.trackers.tracker")}
    assert cross_experiment_imports(edges) == [
        ("hypotrack.experiments.samplers.recorded", "hypotrack.experiments.glmb_benchmark.run"),
        ("hypotrack.experiments.ssa_catalogue.run", "hypotrack.experiments.ssa.trackers")]


def test_shared_modules_import_no_experiment_package():
    """The shared modules sit below every experiment: they never import one."""
    up = sorted((a, b) for a, b in import_graph()
                if a.startswith("hypotrack.experiments.") and a.split(".")[2] in SHARED_MODULES
                and experiment_package(b) is not None)
    assert up == [], f"shared modules importing an experiment package: {up}"


def test_one_package_per_experiment():
    loose = sorted(p.stem for p in EXPERIMENTS.glob("*.py") if p.stem not in SHARED_MODULES)
    assert loose == [], f"experiment modules outside a package: {loose}"
    packages = {p.name for p in EXPERIMENTS.iterdir() if (p / "__init__.py").is_file()}
    assert packages <= RULES, f"packages without a rule of the same name: {packages - RULES}"
    for rule in RULES:
        home = HOSTED.get(rule, rule)
        if home is not None:
            assert home in packages, f"rule {rule} has no package experiments/{home}/"


@pytest.mark.parametrize("package", sorted(p.name for p in EXPERIMENTS.iterdir() if (p / "__init__.py").is_file()))
def test_no_module_named_after_another_experiment(package):
    for module in (EXPERIMENTS / package).glob("*.py"):
        for rule in RULES - {package}:
            assert not module.stem.startswith(rule + "_") and module.stem != rule, \
                f"experiments/{package}/{module.name} is named after the {rule} experiment"


# ---------------------------------------------------------------- objects keep their own state
MAX_MODULE_LINES = 600


def _package(module: str) -> str:
    """The subpackage a module belongs to (``hypotrack.hypotheses.factored.engine`` -> ``hypotrack.hypotheses``);
    a top-level module is its own package."""
    return ".".join(module.split(".")[:2])


def _src_files():
    return {module_name(p): p for p in PKG.rglob("*.py")}


def test_no_module_over_600_lines():
    long = sorted((len(p.read_text().splitlines()), name) for name, p in _src_files().items()
                  if len(p.read_text().splitlines()) > MAX_MODULE_LINES)
    assert long == [], f"modules over {MAX_MODULE_LINES} lines: {long}"


def object_state_edits(tree: ast.AST) -> list:
    """``object.__new__`` calls and ``__dict__`` updates or assignments: objects cloned or filled behind their
    constructors' backs."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr == "__new__" and ast.unparse(node.value) == "object":
            found.append(ast.unparse(node))
        if isinstance(node, ast.Attribute) and node.attr == "__dict__":
            found.append(ast.unparse(node))
    return found


def private_imports_across_packages(name: str, tree: ast.AST, files: dict) -> list:
    """``from <another package> import _name``: an underscore name of another subpackage used here."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            target = resolve(node, name, files[name].name == "__init__.py")
            if not target.startswith("hypotrack") or _package(target) == _package(name):
                continue
            found += [f"{target}.{a.name}" for a in node.names if a.name.startswith("_") and not a.name.startswith("__")
                      and f"{target}.{a.name}" not in files]  # a private module (hypotrack._validation) is shared
    return found


def test_no_object_cloned_or_filled_behind_its_constructor():
    files = _src_files()
    bad = {name: object_state_edits(ast.parse(p.read_text())) for name, p in files.items()}
    assert {k: v for k, v in bad.items() if v} == {}


def test_no_private_name_imported_from_another_package():
    """Private attribute access on other objects is ruff's SLF001 (pyproject.toml, CI's ruff check);
    importing another package's underscore name is checked here."""
    files = _src_files()
    bad = {name: private_imports_across_packages(name, ast.parse(p.read_text()), files) for name, p in files.items()}
    assert {k: v for k, v in bad.items() if v} == {}


def test_the_state_checks_see_what_they_look_for():
    files = {"hypotrack.a.x": Path("x.py"), "hypotrack.b.y": Path("y.py")}
    assert sorted(object_state_edits(ast.parse("g = object.__new__(C)\ng.__dict__.update(f.__dict__)"))) == [
        "f.__dict__", "g.__dict__", "object.__new__"]
    assert private_imports_across_packages("hypotrack.a.x", ast.parse("from ..b.y import _k, ok"), files) == [
        "hypotrack.b.y._k"]
    assert private_imports_across_packages("hypotrack.a.x", ast.parse("from .z import _k"), files) == []
