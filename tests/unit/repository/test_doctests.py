"""The ``Examples`` sections of the package's docstrings run and print what they show.

Every module of ``src/hypotrack`` is imported and its docstrings' examples are run with
:mod:`doctest` (here rather than with ``--doctest-modules``, which would also import the
workflow scripts and notebooks under the test paths). The Stone Soup tracker class is built on
first use inside a function, out of a module scan's reach, so it is added by name.
"""

import doctest
import importlib
import pkgutil

import pytest

import hypotrack

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE

MODULES = sorted(m.name for m in pkgutil.walk_packages(hypotrack.__path__, "hypotrack."))


def _run(obj, name, globs):
    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner(optionflags=FLAGS)
    failures, report = [], []
    for test in finder.find(obj, name, globs=dict(globs)):
        result = runner.run(test, out=report.append)
        if result.failed:
            failures.append(test.name)
    return runner, failures, "".join(report)


@pytest.mark.parametrize("name", MODULES)
def test_module_examples(name):
    module = importlib.import_module(name)
    _, failures, report = _run(module, name, vars(module))
    assert not failures, report


def test_stonesoup_tracker_examples():
    pytest.importorskip("stonesoup")
    from hypotrack.interop import stonesoup as ss

    runner, failures, report = _run(ss.HypotrackTracker, "hypotrack.interop.stonesoup.HypotrackTracker", vars(ss))
    assert not failures, report
    assert runner.tries > 0  # the class does show an example


def test_the_entry_points_show_examples():
    """The public entry points carry an ``Examples`` section with at least one example that runs."""
    from hypotrack import metrics, metrics_trajectory
    from hypotrack.association import counting, lbp
    from hypotrack.hypotheses import presets
    from hypotrack.trackers import gnn

    for obj in (presets.rfisst, presets.homht, presets.glmb, gnn.gnn_associate, metrics.ospa, metrics.gospa,
                counting.count_associations, lbp.lbp_marginals, metrics_trajectory.trajectory_gospa):
        assert "Examples\n" in obj.__doc__, obj.__qualname__
        tests = doctest.DocTestFinder().find(obj)
        assert any(t.examples for t in tests), obj.__qualname__
