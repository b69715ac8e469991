"""A selective ``quiet`` / ``recording`` scope takes the subclasses of its categories (review27).

Planted bug of review27 (docs/MUTATION.md, round 27) that the fixes-41-c file let through:
the scope matched the category exactly (``category in categories``), so
``quiet(UserWarning)`` let a ``BiasRuleWarning`` (a ``UserWarning`` subclass) through.
Reference: Python's own filter, ``warnings.simplefilter("ignore", UserWarning)``, which
ignores the subclasses too (the docstring's "those categories (and subclasses)").
"""

from __future__ import annotations

import warnings

from modalinfo.common.quiet import quiet, recording, warn
from modalinfo.information import BiasRuleWarning


def _shown(block):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        block()
    return [w.category for w in caught]


def test_python_filter_reference_ignores_the_subclass():
    def block():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)
            warnings.warn("biased", BiasRuleWarning, stacklevel=1)
    assert _shown(block) == []


def test_quiet_of_a_category_silences_its_subclasses():
    def block():
        with quiet(UserWarning):
            warn("biased", BiasRuleWarning, stacklevel=1)
            warn(BiasRuleWarning("biased too"), stacklevel=1)
            warn("kept", RuntimeWarning, stacklevel=1)
    assert _shown(block) == [RuntimeWarning]


def test_recording_of_a_category_keeps_its_subclasses():
    def block():
        with recording(UserWarning) as kept:
            warn("biased", BiasRuleWarning, stacklevel=1)
        assert [w.category for w in kept] == [BiasRuleWarning]
        assert isinstance(kept[0].message, BiasRuleWarning)
    assert _shown(block) == []
