"""hypotrack's trackers are a Stone Soup plugin: the package's ``stonesoup.plugins`` entry point makes them
importable from Stone Soup's own namespace (``pip install`` registers it)."""

from importlib.metadata import entry_points

import pytest


def test_the_entry_point_is_registered_and_names_the_adapter():
    found = {e.name: e.value for e in entry_points(group="stonesoup.plugins")}
    assert found.get("hypotrack") == "hypotrack.interop.stonesoup"


def test_stonesoup_imports_the_tracker_through_its_plugins():
    pytest.importorskip("stonesoup")
    from stonesoup.plugins.hypotrack import HypotrackTracker
    from stonesoup.tracker.base import Tracker

    from hypotrack.interop.stonesoup import HypotrackTracker as ours

    assert HypotrackTracker is ours and issubclass(HypotrackTracker, Tracker)
