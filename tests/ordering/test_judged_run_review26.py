"""Planted-bug review 26 (stop 50): ``cost.judged_run`` nests and restores its flag.

Round 40 PART a T25 replaced ``ordering_stability``'s ``catch_warnings`` block by a
thread-local flag: "Within: this thread's check_ordering_seconds neither refuses nor
warns". Inside an outer run, an inner run's end must leave the outer's flag set, and the
outer's end must clear it (the state before). Reference: the docstring's promise and
``check_ordering_seconds``' own refusal above ``max_seconds`` outside any run. Plant
R26-Q2 (the flag cleared, not restored, at an inner run's end) escaped
tests/common/test_warnings_lock_round40.py.
"""

import pytest

from modalinfo.ordering import cost


def _over():
    cost.check_ordering_seconds(1e6, "the ordering is estimated at 1e6 s of CPU",
                                "use fewer modes", max_seconds=1.0)


def test_an_inner_judged_run_leaves_the_outer_one_judged():
    with pytest.raises(ValueError, match="max_seconds"):
        _over()  # outside: refused
    with cost.judged_run():
        with cost.judged_run():
            _over()
        _over()  # still inside the outer run: neither refused nor warned
    with pytest.raises(ValueError, match="max_seconds"):
        _over()  # after: refused again
