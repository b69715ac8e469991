"""Least CPU time of a greedy MI ordering: what the command line and batch refuse before work.

One MI estimate on ``n`` samples costs ``MI_SECONDS_PER_SAMPLE[estimator](n) * n`` CPU
seconds, a little below the times measured (``time.process_time`` of
``MutualInformation.score`` at n = 1e4, 1e5, 4e5 on this project's 2-core machine,
2026-11-28: ksg 6.4, 10.4, 13.7 us per sample, growing as log2 n for its k-d tree
queries: the lower bound of the package's one KSG cost model,
:func:`~modalinfo.information.ksg.ksg_seconds_per_sample`; kde 0.19-0.24 us
(binned); gaussian 0.13-0.23 us; histogram 0.03-0.06 us). A greedy ordering of M
modes makes at least ``2 M - 2`` estimates (every mode at the first step, at least one
at each later step but the last, which completes the wavefront), and one more per
bootstrap replicate, so :func:`least_ordering_seconds` is a lower bound of
the real time: what it refuses cannot finish sooner. A bootstrap replicate re-estimates
the MI of every step along the order and of its swapped rival (``_cumulative_mi`` and
``_swapped_mi`` of :mod:`modalinfo.ordering.orderings`): at least ``2 M - 3`` estimates
each. Counting one per replicate let ``reorder --budget 600000 --resamples 1000`` on 300
modes (about 6 h) through as 19 s (adversarial round 10 PART b, row B13).
"""

from __future__ import annotations

from modalinfo.information.ksg import ksg_seconds_per_sample

__all__ = ["MAX_ORDERING_SECONDS", "MI_SECONDS_PER_SAMPLE", "least_ordering_seconds"]

#: CPU seconds per sample of one MI estimate on n samples (module notes)
MI_SECONDS_PER_SAMPLE = {
    "ksg": lambda n: ksg_seconds_per_sample(n, 2, least=True),
    "kde": lambda n: 1.5e-7,
    "gaussian": lambda n: 1e-7,
    "histogram": lambda n: 2e-8,
}
#: Most CPU time a run of MI orderings may be estimated to take before it is refused [s]
MAX_ORDERING_SECONDS = 3600.0


def least_ordering_seconds(estimator: str, n_samples: int, n_modes: int,
                           n_resamples: int = 0, n_orderings: int = 1) -> tuple[float, int]:
    """Return (least CPU seconds, least number of MI estimates) of greedy MI orderings.

    Parameters
    ----------
    estimator : str
        MI method name; another (an estimator object) costs 0 here (unknown).
    n_samples : int
        Samples per MI estimate (``min(budget, frames x pupil pixels)``).
    n_modes : int
        Modes ordered, M.
    n_resamples : int
        Bootstrap replicates of each ordering (``2 M - 3`` estimates each, at least).
    n_orderings : int
        MI orderings run.
    """
    rate = MI_SECONDS_PER_SAMPLE.get(estimator) if isinstance(estimator, str) else None
    calls = n_orderings * (max(2 * n_modes - 2, 1)
                           + max(n_resamples, 0) * max(2 * n_modes - 3, 1))
    if rate is None or n_orderings < 1:
        return 0.0, calls
    return calls * n_samples * rate(n_samples), calls
