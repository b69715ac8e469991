"""Shared pytest configuration.

- Long end-to-end runs (``@pytest.mark.slow``: the full paper figures on the default
  synthetic log) run only with ``--runslow``. The statistical-validity checks
  (coverage of intervals, levels of tests) are in the default tier, sized so that
  their binomial tolerances are computed in the test.
- Hypothesis: no per-example deadline (the first example of a test may pay a numba
  compilation, and the machine is shared), and under CI (``CI`` set) a derandomised
  search so that a run is reproducible; locally the search stays random.
"""

import os

import pytest
from hypothesis import settings

settings.register_profile("modalinfo", deadline=None, print_blob=True)
settings.register_profile("modalinfo-ci", deadline=None, print_blob=True, derandomize=True)
settings.load_profile("modalinfo-ci" if os.environ.get("CI") else "modalinfo")


def pytest_addoption(parser):
    parser.addoption(
        "--runslow", action="store_true", default=False, help="also run tests marked slow"
    )


def pytest_collection_modifyitems(config, items):
    if config.getoption("--runslow"):
        return
    skip = pytest.mark.skip(reason="long end-to-end run: run with --runslow")
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)


@pytest.fixture
def pdf_backend():
    """matplotlib on the ``pdf`` backend for the test, the one before put back after.

    A caller's backend that drawing must leave alone (audit 10-state, round 45 PART a G15).
    """
    import matplotlib

    before = matplotlib.get_backend()
    matplotlib.use("pdf")
    yield
    matplotlib.use(before)


@pytest.fixture
def cheap_figure5_predictors(monkeypatch):
    """Figure 5's three predictors replaced by a stub whose fits cost nothing.

    For tests of what Figure 5 does around ``evaluate`` (its notes, its warnings), not of
    the fits: the stub forecasts zeros and has no intervals.
    """
    import numpy as np

    import modalinfo.forecast as forecast

    class Cheap:
        def __init__(self, *args, **kwargs):
            pass

        @classmethod
        def paper(cls, *args, **kwargs):
            return cls()

        def fit(self, x):
            return self

        def _forecast_path(self, x, h):
            return np.zeros((x.shape[0], 1, 1)), None

        def predict_interval(self, x):
            return None

    for name in ("ARMAPredictor", "LinearPredictor", "NeuralNetPredictor"):
        monkeypatch.setattr(forecast, name, Cheap)
    return Cheap
