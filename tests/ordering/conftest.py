"""Helpers shared by the ordering tests (reference: the calls counted as they are made).

- :class:`CountingMI`: a histogram ``MutualInformation`` that counts its ``score`` calls
  (test_least_time_structure, test_greedy_count_edge_review10).

Test files import it (``from .conftest import CountingMI``).
"""

from modalinfo.information import MutualInformation


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
