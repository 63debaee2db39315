"""The samplers are used through their public names: no module of another package imports an
underscore name of hypotrack.association (nor of hypotrack.reporting or hypotrack.scenarios), so the
generators of hypotrack.hypotheses are adapters over the public kernels of association.samplers."""

import ast
from functools import cache
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[4] / "src"
GUARDED = ("association", "reporting", "scenarios")


@cache
def private_imports() -> tuple[tuple[str, str, str], ...]:
    """(importer, imported module, name) for every underscore name imported across packages."""
    found = []
    for path in sorted((SRC / "hypotrack").rglob("*.py")):
        parts = list(path.relative_to(SRC).with_suffix("").parts)
        importer = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        package = parts[:-1]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not isinstance(node, ast.ImportFrom):
                continue
            base = package[: len(package) - (node.level - 1)] if node.level else []
            target = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:
                if alias.name.startswith("_") and not alias.name.startswith("__"):
                    if target.split(".")[:2] != importer.split(".")[:2]:  # another package of hypotrack
                        found.append((importer, target, alias.name))
    return tuple(found)


@pytest.mark.parametrize("package", GUARDED)
def test_no_other_package_imports_a_private_name(package):
    crossing = [f for f in private_imports() if f[1].startswith(f"hypotrack.{package}")]
    assert crossing == []


def test_the_generators_import_public_names_only():
    assert [f for f in private_imports() if f[0] in ("hypotrack.hypotheses.gibbs", "hypotrack.hypotheses.generators")] == []


def test_the_check_sees_a_private_import():
    """hypotheses -> gaussian's private helpers are such imports (outside the guarded packages)."""
    assert any(f[0].startswith("hypotrack.hypotheses") and f[1] == "hypotrack.gaussian" for f in private_imports())
