"""tests/unit mirrors src/hypotrack, so a test shows where it goes (and the mutation runner finds it).

The tests of ``src/hypotrack/a/b.py`` live in ``tests/unit/a/`` (``test_b*.py`` or a concern of
the subpackage); tests of top-level modules in ``tests/unit/`` itself; tests of the repository as
a whole in ``tests/unit/repository/``.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[3]
UNIT = ROOT / "tests" / "unit"
PKG = ROOT / "src" / "hypotrack"
# Top-level test files about the package as a whole rather than one module.
PACKAGE_WIDE = {"test_bad_input_catalogue.py"}


def test_every_unit_test_folder_is_a_subpackage():
    folders = {p.parent.relative_to(UNIT) for p in UNIT.rglob("test_*.py")} - {Path(".")}
    stray = sorted(str(f) for f in folders
                   if f.parts[0] != "repository" and not (PKG / f / "__init__.py").is_file())
    assert not stray, f"tests/unit/<folder> must mirror a subpackage of src/hypotrack: {stray}"


def test_top_level_unit_tests_name_top_level_modules():
    modules = {p.stem.lstrip("_") for p in PKG.glob("*.py") if p.stem != "__init__"}
    for test in UNIT.glob("test_*.py"):
        if test.name in PACKAGE_WIDE:
            continue
        stem = test.stem.removeprefix("test_")
        assert any(stem == m or stem.startswith(m + "_") for m in modules), (
            f"{test.name}: a test in tests/unit/ names a top-level module of src/hypotrack ({sorted(modules)}); "
            "a subpackage's tests go in its folder")


def test_no_package_markers_or_stray_files():
    """--import-mode=importlib needs no __init__.py, and same-named files in different folders are fine."""
    assert not list(UNIT.rglob("__init__.py"))
    assert not [p for p in UNIT.rglob("*.py") if not p.name.startswith(("test_", "conftest"))]
