"""``closedloop``'s result loader keeps only the unchecked-result warning as a note (review27).

Planted bug of review27 (docs/MUTATION.md, round 27) that the fixes-41-c files let
through: ``recording()`` of every category in ``cli._load_result`` (for
``recording(UncheckedResultWarning)``) turned any other warning of the load into the
"unchecked" note and marked a verified result unverified. Reference: the loader's
comment ("anything else goes on as it would have") and Python's ``warnings`` machinery
showing that other warning to the caller's ``catch_warnings(record=True)``.
"""

from __future__ import annotations

import argparse
import warnings

from closedloop import cli
from closedloop.result import SimulationResult, UncheckedResultWarning
from modalinfo.common.quiet import warn


def _load(monkeypatch, category):
    def fake_load(path):
        warn(category(f"{path}: a warning of the load"), stacklevel=2)
        return "loaded"
    monkeypatch.setattr(SimulationResult, "load", staticmethod(fake_load))
    args = argparse.Namespace(result="r.h5", command="info")
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        result, verified = cli._load_result(args)
    return result, verified, [w.category for w in shown], getattr(args, "_notes", None)


def test_another_warning_of_the_load_is_shown_and_the_result_stays_verified(monkeypatch):
    result, verified, shown, notes = _load(monkeypatch, RuntimeWarning)
    assert result == "loaded" and verified is True
    assert shown == [RuntimeWarning] and not notes


def test_the_unchecked_warning_is_a_note_and_the_result_unverified(monkeypatch):
    result, verified, shown, notes = _load(monkeypatch, UncheckedResultWarning)
    assert verified is False and shown == []
    assert notes and "a warning of the load" in notes[0]
