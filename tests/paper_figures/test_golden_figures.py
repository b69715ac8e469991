"""Golden numbers of ``python -m paper_figures --quick``: every JSON file and report number.

Reference: the committed ``tests/golden/figures.json`` (written by
``python tests/golden/regenerate.py --only figures``): each JSON file the quick run
writes, leaf by leaf, and every number of ``report.md`` (comparison-table rows and the
sentences of every section) keyed by its section and the text around it, as printed.
Run times and numbers resting on this machine's measurements are left out. Tolerance:
``golden_numbers.RTOL["figures"]`` (1e-6; the float error across CPUs measured against
``NUMBA_CPU_NAME=generic`` and OpenBLAS's Sandybridge kernels; docs/TESTING.md, "Golden
numbers"), ``RTOL_NN`` (0.2) for the numbers of the trained neural nets, which moved by
up to 0.76 % there; Figure 7's solar loop runs at their measured tolerances (the ARMA
fitted in the loop 3 x 1.38 %, the rest 3 x 7.4e-6) and an NN's Diebold-Mariano
statistic by its sign (``golden_numbers.tolerance``, golden40); names and counts
exactly; a printed number also within one unit of its last digit. Reads the session's
one quick run (``conftest.py``); the presets and the shipped logs are compared in
``tests/test_golden.py``.
"""

import importlib.util
import sys
from pathlib import Path

import pytest

_SPEC = importlib.util.spec_from_file_location(
    "golden_numbers", Path(__file__).resolve().parents[1] / "golden" / "golden_numbers.py")
g = sys.modules.get("golden_numbers") or importlib.util.module_from_spec(_SPEC)
if "golden_numbers" not in sys.modules:
    sys.modules["golden_numbers"] = g
    _SPEC.loader.exec_module(g)


@pytest.fixture(scope="module")
def current(quick_run):
    return g.figure_numbers(quick_run.out)


@pytest.mark.parametrize("name", sorted(g.read("figures")))
def test_quick_run_numbers_match_the_golden_reference(current, name):
    reference = g.read("figures")
    assert sorted(current) == sorted(reference), "a JSON file appeared or went: regenerate"
    moved = g.differences("figures", {name: reference[name]}, {name: current[name]},
                          g.RTOL["figures"], context=reference)
    if moved:
        shown = "\n  ".join(moved[:40]) + ("\n  ..." if len(moved) > 40 else "")
        pytest.fail(f"{len(moved)} golden number(s) of {name} (quick run) moved (relative "
                    f"tolerance {g.RTOL['figures']:g}, printed numbers one unit of their "
                    f"last digit):\n  {shown}\nIf the change is intended: "
                    f"{g.REGENERATE.format(section='figures')}.", pytrace=False)
