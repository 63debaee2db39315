"""Scenarios make data, experiments draw it: no module of hypotrack.scenarios imports matplotlib
(the scenario figure lives in hypotrack.experiments.ssa.scenario_figures)."""

import ast
from pathlib import Path

SCENARIOS = Path(__file__).resolve().parents[3] / "src" / "hypotrack" / "scenarios"


def drawing_imports(path: Path) -> list[str]:
    """The matplotlib imports of a module (module level or inside a function)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
            [node.module or ""] if isinstance(node, ast.ImportFrom) else []
        found += [n for n in names if n.split(".")[0] == "matplotlib"]
    return found


def test_no_scenario_module_draws():
    modules = sorted(SCENARIOS.rglob("*.py"))
    assert len(modules) > 5
    drawing = {str(p.relative_to(SCENARIOS)): drawing_imports(p) for p in modules}
    assert {k: v for k, v in drawing.items() if v} == {}


def test_the_check_sees_a_drawing_import(tmp_path):
    module = tmp_path / "m.py"
    module.write_text("def f():\n    from matplotlib.patches import Circle\n    import matplotlib.pyplot as plt\n")
    assert drawing_imports(module) == ["matplotlib.patches", "matplotlib.pyplot"]
