"""The deprecated ``simulate(predictor='oracle')`` warns at the caller's line (round 24 a, W13).

Reference: Python's default warning filters (``python -W`` documentation): a
``DeprecationWarning`` is shown by default only when attributed to ``__main__``, i.e.
when its ``stacklevel`` reaches the user's line. Before the fix it named
``closedloop/simulation.py``, so a user's script never saw it. The check: the recorded
warning's file and line are this test's call, read from the frame.
"""

from __future__ import annotations

import dataclasses
import inspect
import warnings

from closedloop import presets, simulate


def test_oracle_string_deprecation_names_the_callers_line():
    c = presets.get("table1")
    small = dataclasses.replace(c, layers=(c.layers[0],), wfss=(c.wfss[0],),
                                dms=(dataclasses.replace(c.dms[0], n_modes=9),))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        line = inspect.currentframe().f_lineno + 1
        simulate(small, 0.01, predictor="oracle", seed=0)
    mine = [w for w in caught if issubclass(w.category, DeprecationWarning)
            and "predictor='oracle'" in str(w.message)]
    assert mine
    assert all((w.filename, w.lineno) == (__file__, line) for w in mine), \
        [(w.filename, w.lineno) for w in mine]
