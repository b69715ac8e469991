"""Golden numbers of Figure 5 at the paper's settings: every JSON leaf and report number.

Stop 57, fix51-c item 7: the full Figure 5 (``python -m paper_figures --only 5``: every
mode of both shipped logs; ``--quick`` evaluates the first 5) was in no golden file
(docs/ADVERSARIAL.md, fix48-d: "the full Figure 5's numbers are in no golden file").
Reference: the committed ``tests/golden/fig5.json`` (written by ``python
tests/golden/regenerate.py --only fig5``): each JSON file the run writes
(``fig5_forecast.json``, ``fig5_forecast_closedloop.json``), leaf by leaf, and every
number of its ``report.md`` (the comparison rows and Figure 5's sections) keyed by its
section and the text around it, as printed; run times are left out. Tolerances: the
classes of the quick run's goldens (``golden_numbers.tolerance``: ``RTOL`` 1e-6, the
trained NNs' numbers at ``RTOL_NN`` 0.2, an NN's Diebold-Mariano statistic by its sign;
a printed number also within one unit of its last digit; docs/TESTING.md, "Golden
numbers"). One BLAS thread, as the reference. Cost: ~25 s of CPU (measured under load:
170 s of wall time, 0.48 GB peak RSS); marked ``reproducibility`` with the presets'
and the logs' goldens (CI runs them also under ``NUMBA_CPU_NAME=generic``).
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
def current(tmp_path_factory):
    from paper_figures.__main__ import main

    out = tmp_path_factory.mktemp("fig5") / "out"
    with g.limit_blas_threads():
        assert main(["--out", str(out), *g.FIG5_ARGS]) == 0
    return g.figure_numbers(out)


@pytest.mark.reproducibility
@pytest.mark.parametrize("name", sorted(g.read("fig5")))
def test_figure5_numbers_match_the_golden_reference(current, name):
    reference = g.read("fig5")
    assert sorted(current) == sorted(reference), "a JSON file appeared or went: regenerate"
    moved = g.differences("fig5", {name: reference[name]}, {name: current[name]},
                          g.RTOL["fig5"], context=reference)
    if moved:
        shown = "\n  ".join(moved[:40]) + ("\n  ..." if len(moved) > 40 else "")
        pytest.fail(f"{len(moved)} golden number(s) of {name} (Figure 5, --only 5) moved "
                    f"(relative tolerance {g.RTOL['fig5']:g}, printed numbers one unit of "
                    f"their last digit):\n  {shown}\nIf the change is intended: "
                    f"{g.REGENERATE.format(section='fig5')}.", pytrace=False)
