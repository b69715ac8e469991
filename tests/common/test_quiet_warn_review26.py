"""Planted-bug review 26 (stop 50): ``quiet.warn`` attributes a warning to the user's line.

Round 40 PART a (fixes 40-c) routed every package warning through
``modalinfo.common.quiet.warn``, whose ``stacklevel`` "counts from the caller of this
function, as ``warnings.warn``'s from its own caller". A warning raised for the caller
must name the caller's file and line (so that Python's default filter shows it, and
shows where), not quiet.py. Reference: ``warnings.warn`` itself, called the same way
from this file, and this file's name. Plant R26-Q1 (``stacklevel`` not shifted by one:
every package warning attributed to quiet.py) escaped
tests/information/test_quiet_quarters_round40.py and
tests/common/test_warnings_lock_round40.py.
"""

import inspect
import warnings

import numpy as np

from modalinfo.common import quiet
from modalinfo.telemetry import ModalLog


def test_warn_names_its_callers_caller_as_warnings_warn_does():
    def direct():
        warnings.warn("direct", UserWarning, stacklevel=2)

    def routed():
        quiet.warn("routed", UserWarning, stacklevel=2)

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1
        direct(); routed()  # noqa: E702 - one line, both attributed to it
    assert [(w.filename, w.lineno) for w in rec] == [(__file__, line)] * 2


def test_a_package_warning_points_at_the_users_line():
    t_ms = np.arange(200) * 1.0  # a 1 kHz loop's times in ms: the rate-floor warning
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1
        ModalLog(np.random.default_rng(0).standard_normal((200, 3)), timestamps=t_ms)
    assert len(rec) == 1 and "below 10 Hz" in str(rec[0].message)
    assert (rec[0].filename, rec[0].lineno) == (__file__, line)
