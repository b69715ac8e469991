"""Helpers shared by the ordering tests (reference: the calls counted as they are made).

- :class:`CountingMI`: a histogram ``MutualInformation`` that counts its ``score`` calls
  (test_least_time_structure, test_greedy_count_edge_review10).

- ``quiet_warnings``: a fixture that silences the warnings a coarse pupil or the K-L
  geometry gives, for tests about something else (test_compare_bases_round35,
  test_unused_options_round36: ``pytestmark = pytest.mark.usefixtures("quiet_warnings")``).

Test files import it (``from .conftest import CountingMI``).
"""

import warnings

import pytest

from modalinfo.information import MutualInformation


@pytest.fixture
def quiet_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse pupil's and K-L geometry's notes
        yield


class CountingMI:
    """A histogram MutualInformation that counts its score calls."""

    def __init__(self):
        self.inner = MutualInformation(method="histogram", units="nats")
        self.calls = 0

    def fit(self, x):
        self.inner.fit(x)
        return self

    def score(self, y):
        self.calls += 1
        return self.inner.score(y)
