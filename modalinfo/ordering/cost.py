"""Least CPU time of a greedy MI ordering: what the command line and batch refuse before work.

One MI estimate on ``n`` samples costs ``MI_SECONDS_PER_SAMPLE[estimator](n) * n`` CPU
seconds, a little below the times measured (``time.process_time`` of
``MutualInformation.score`` at n = 1e4, 1e5, 4e5 on this project's 2-core machine,
2026-11-28: ksg 6.4, 10.4, 13.7 us per sample, growing as log2 n for its k-d tree
queries, and 3.4, 3.9, 5.5 us at n = 1e3, 1e4, 1e5 in round 12: the lower bound of
the package's one KSG cost model,
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

**The per-call term** (audit 11-cost, issue 27). Each estimate also costs a fixed
``MI_SECONDS_PER_CALL[estimator]`` whatever its size (Python dispatch, the bins' edges or
the KDE's grid, the copula's set-up), which dominates small samples: ``reorder
--stability 1`` (4000 one-frame windows of 3,228 samples) was counted 14 s and took
414 s. Measured (``time.process_time`` of ``MutualInformation.score`` after ``fit``,
median of 3 batches, one BLAS thread, load 3-4, benchmarks/bench_cost_models.py): at
n = 30 histogram 73 us, kde 4.2 ms (3.6 ms at n = 1000), gaussian 154 us, ksg 359 us (275 us
in a second run); the constants are 0.55-0.7 of these, so the bound stays below every
time measured.
The histogram's time grows as ~sqrt(n) from 30 to 1e5 samples (73, 121, 153, 297, 378,
502, 1378 us at n = 30, 100, 300, 1e3, 3,228, 1e4, 1e5): its per-sample rate is the
lower envelope ``max(1e-8, 3.3e-6 / sqrt(n))`` s (0.6-0.8 of each row beyond the call
term; the flat 2e-8 before was 5x low at 3,228 samples and, with the call term, above
the 1.38 ms measured at 1e5). Rule: least seconds of one estimate =
``MI_SECONDS_PER_CALL + n x MI_SECONDS_PER_SAMPLE(n)``.

**The greedy's calls** (``method="mi_greedy"``, the command line's default):
``order_modes``' search ``"auto"`` scores every remaining mode at every step up to
``_EXHAUSTIVE_MAX_MODES`` modes (``M (M + 1) / 2 - 1`` estimates: every mode at each
step with at least 2 left); above it, the screened search scores every mode at the
first step and every one left once ``_EXHAUSTIVE_TAIL`` or fewer remain, at least one
at each step between. For 27 modes that is 377 estimates an ordering (measured 387 with
the swapped rivals), where ``2 M - 2`` = 52 were counted. Not counted (so the bound
stays a bound): the fit of ``Phi_ref`` and the swapped rivals the screened search did
not score (the gathering of the contributions is counted since leftovers 13, below).

**The screens and the replicates' samples** (leftovers 13-cost, issue 27). Every
``MutualInformation.score`` also validates its ``y`` and runs the copy and
union-of-curves screens of :mod:`modalinfo.information.api` (sorts of the first 32 and
1024 samples, a TWO-NN dimension on 128 points) whatever the estimator: measured
0.30-0.34 ms per score at n = 1e3 - 25,280, 0.45-0.49 ms at 1e5, 0.65-0.69 ms at 2e5
(random pairs, load 4), so ``SCREEN_SECONDS_PER_CALL + n SCREEN_SECONDS_PER_SAMPLE`` =
0.25 ms + 1.5 ns n is added to each estimate:
half of the histogram's time at 25,280 samples. Each bootstrap replicate (and the
ordering itself) gathers the M x n contributions of its samples and sums them for
Phi_ref: 1.9-7 ns per mode and sample (25,280 samples x 50 modes 1.9 ns, x 500 modes 5.4
ns; 2e5 x 500 7.0 ns), ``GATHER_SECONDS_PER_ENTRY`` = 1.5 ns. And
the count is that of the calls made (counted on ``MutualInformation.score``,
tests/information/test_cost_left13.py): ``"mi_marginal"`` scores every mode, then the
cumulative MI and the swapped rival of every step but the last (``3 M - 2``); a replicate
``2 M - 2`` (the cumulative MI and the swapped rival of each step but the last; ``2 M -
3`` was counted). Round 13's ``mi_marginal`` ordering of 150 modes x 20 frames (25,280
samples, 40 replicates) made 12,368 estimates and took 21 s of CPU where the bound said
6.9 s (adversarial round 13). Measured / modelled at 50, 150, 500 modes (25,824 samples,
``benchmarks/bench_ordering_cost.py``): 2.03, 2.04, 2.14 before, 1.29, 1.30, 1.37 after
(benchmarks/RESULTS.md, "Orderings' cost and the kde rule's quarters, leftovers 13"). The
gathering's CPU per entry at 2e5 samples, re-measured at load 15 (leftovers 14-misc):
6-11 ns at 0.22 GiB, 12-17 at 0.75, 17-20 at 1.49 GiB, no step above 1 GB (the 68 ns once
seen at 1.6 GB was not reproduced); the constant stays a lower envelope.

**Re-measured on a grid** (fixes 47-b, issue 27; adversarial round 46 PART a, A03a /
A03c: 3.8-5.3x below the CPU at 1000 modes x 200,000 samples). ``order_modes``'
``time.process_time`` over estimators (histogram, gaussian, kde, ksg) x 1e3-2e5 samples
per estimate x 20, 200, 1000 modes x 0 / 20 replicates x ``mi_marginal`` / ``mi_greedy``
(benchmarks/bench_ordering_cost.py ``--grid``, medians of 3, load 2-10 on the 2 shared
cores; benchmarks/RESULTS.md "fix47-b"): the estimate was 1.4-7.6x below every cell.
(1) The screened greedy's count: a step that scores one mode has not scored the next
step's mode, so ``_swapped_mi`` estimates that rival afterwards: at least two
estimates per screened step, where one was counted (a 40-mode screened ordering of
variances 1.3x apart makes exactly the 221 counted now, 198 before); 200 and 1000
modes made 3.3-4.6 a step on the grid's logs, which the bound cannot count. (2) The
estimators' per-sample terms, raised to what the module's measurements above still
allow (every one of them stays above the bound: histogram ``max(1.2e-8, 4e-6 /
sqrt(n))``, was ``max(1e-8, 3.3e-6 / sqrt(n))``: a sort-based estimate costs no less a
sample at 2e5 than at 1e5; gaussian 1.2e-7, was 1e-7; kde 3 ms + 300 ns n, was 2.5 ms + 150 ns n).
(3) Not counted, as the bound must hold on a quiet machine: one score of 1,000
samples took 1.1-1.3 ms at load 7-8 (histogram, gaussian), where the same work
measured 0.6 ms at load 3-4 (the notes above); the gather 3.1-5.3 ns per entry up to
200 modes, 14-18 ns at 1000 modes x 1e5-2e5 (load 10), 1.9 ns at load 4. The measured
CPU is now 1.1-4.6x the estimate on the 65 cells run (1.4-7.6x before): within 2x
on 22 of them (13 before), 3.2-4.6x for the greedy at 200-1000 modes (its 3.3-4.6 estimates a
step) and at 200,000 samples x 200-1000 modes (load 9-10). The estimate stays a lower
bound and says so ("or more (a lower bound)", :func:`seconds_text`), as does
``reorder``'s note since fixes 47-b; 2.4x the bound would be within 2x of every cell
(0.48-1.92), an "about" estimate that is no longer a bound.

**Before the work.** :func:`~modalinfo.ordering.order_modes` checks
:func:`least_ordering_seconds` before any estimate, as ``reorder`` and ``batch`` do: it
refuses above its ``max_seconds`` (default :data:`MAX_ORDERING_SECONDS`, the command
line's hour) and warns (:class:`OrderingCostWarning`), naming the estimate and how to
shorten it, above :data:`NOTE_ORDERING_SECONDS`;
:func:`~modalinfo.ordering.ordering_stability` applies the same rule to the sum of its
orderings (leftovers 14-misc). The command line says its own note, in its flags, and
silences the library's.

**Memory** (leftovers 14-misc, issue 27). An MI ordering holds the float64
contributions of every mode at every sample (``M x n``), and its bootstrap gathers a
replicate's while the ordering's and the previous replicate's are still held:
:func:`ordering_memory_bytes`, ``8 M n`` bytes without replicates, ``3 x 8 M n`` with,
plus :data:`PER_SAMPLE_ARRAYS` float64 arrays of ``n`` (the per-sample indices and sums:
tracemalloc measured 15 of them without replicates, 7 with; fixes 42, S16).
``order_modes`` refuses, before any work, an ordering whose arrays exceed
:func:`~modalinfo.common.memory.usable_memory_bytes`; ``reorder`` checks the same
estimate with the log's copies (1000 modes x 2e5 samples: 1.6 GB, 4.8 GB with
replicates).
"""

from __future__ import annotations

import contextlib
import math
import threading
from collections.abc import Iterator

from modalinfo.common.quiet import warn
from modalinfo.information.ksg import ksg_seconds_per_sample

__all__ = ["CONTRIBUTION_BYTES", "GATHER_SECONDS_PER_ENTRY", "MAX_ORDERING_SECONDS",
           "MI_SECONDS_PER_SAMPLE", "MI_SECONDS_PER_CALL", "NOTE_ORDERING_SECONDS",
           "OrderingCostWarning", "SCREEN_SECONDS_PER_CALL", "SCREEN_SECONDS_PER_SAMPLE",
           "check_ordering_seconds", "judged_run", "least_ordering_seconds",
           "least_ordering_calls", "seconds_text",
           "ordering_memory_bytes"]

#: ``order_modes(search="auto")`` scores every candidate at every step up to this many
#: modes (here, not in :mod:`modalinfo.ordering.orderings`, which imports this module).
_EXHAUSTIVE_MAX_MODES = 64
#: The screened search scores every remaining mode once this few are left (<= 136
#: scores): near Phi_ref the histogram MI saturates (bins capped at sqrt(n)) and its
#: gains, 0.1-0.3 nats per step there, depart most from the Gaussian key.
_EXHAUSTIVE_TAIL = 16
#: CPU seconds per sample of one MI estimate on n samples (module notes)
MI_SECONDS_PER_SAMPLE = {
    "ksg": lambda n: ksg_seconds_per_sample(n, 2, least=True),
    "kde": lambda n: 3e-7,
    "gaussian": lambda n: 1.2e-7,
    "histogram": lambda n: max(1.2e-8, 4e-6 / math.sqrt(max(n, 1))),
}
#: CPU seconds of one MI estimate whatever its size, a lower bound (module notes)
MI_SECONDS_PER_CALL = {"ksg": 1.5e-4, "kde": 3e-3, "gaussian": 1e-4, "histogram": 4e-5}
#: CPU seconds of the checks of each ``MutualInformation.score`` (validation, copy and
#: curve screens), per call and per sample, a lower envelope (module notes)
SCREEN_SECONDS_PER_CALL = 2.5e-4
SCREEN_SECONDS_PER_SAMPLE = 1.5e-9
#: CPU seconds per mode and sample of gathering (and summing) the contributions, once for
#: the ordering and once per bootstrap replicate (module notes)
GATHER_SECONDS_PER_ENTRY = 1.5e-9
#: Most CPU time a run of MI orderings may be estimated to take before it is refused [s]
#: (``reorder``, ``batch``, and ``order_modes``' default ``max_seconds``)
MAX_ORDERING_SECONDS = 3600.0
#: Estimated CPU time above which ``order_modes`` warns before the work [s]
NOTE_ORDERING_SECONDS = 60.0
#: Bytes of one contribution (float64), per mode and sample
CONTRIBUTION_BYTES = 8
#: float64 arrays of one value per sample an ordering holds beside its contributions
#: (tracemalloc peak of order_modes, 10 and 27 modes x 200,000 samples: 14.9 without
#: replicates, 7.2 with, counted with room for numpy's temporaries; round 42 PART b, S16)
PER_SAMPLE_ARRAYS = 20


class OrderingCostWarning(UserWarning):
    """An MI ordering (or a run of them) is estimated above :data:`NOTE_ORDERING_SECONDS`.

    Its own class so that a caller that has told the user in its own words (the command
    line, in its flags) can silence it without silencing other warnings.
    """


def ordering_memory_bytes(n_modes: int, n_samples: int, n_resamples: int = 0) -> float:
    """Peak bytes of an MI ordering's contribution arrays (module notes).

    Parameters
    ----------
    n_modes : int
        Modes ordered, M.
    n_samples : int
        Samples per MI estimate, n.
    n_resamples : int
        Bootstrap replicates; with any, a replicate's M x n array is gathered while the
        ordering's and the previous replicate's are held (3 copies).

    Returns
    -------
    float
        ``CONTRIBUTION_BYTES x (copies x M + PER_SAMPLE_ARRAYS) x n`` [bytes].
    """
    copies = 3 if n_resamples > 0 else 1
    m, n = max(int(n_modes), 0), max(int(n_samples), 0)
    return float(CONTRIBUTION_BYTES * (copies * m + (PER_SAMPLE_ARRAYS if m else 0)) * n)


def least_ordering_calls(n_modes: int, method: str = "mi_marginal",
                         search: str = "auto") -> int:
    """Least number of MI estimates of one ordering of ``n_modes`` modes (no bootstrap).

    ``"mi_greedy"``: every mode at every step up to ``_EXHAUSTIVE_MAX_MODES`` modes
    (``M (M + 1) / 2 - 1``); above, every mode at the first step and at each step with
    ``_EXHAUSTIVE_TAIL`` or fewer left, at least two for each step between: a step that
    scores one mode only has not scored the next step's mode, whose swapped rival
    ``_swapped_mi`` then estimates (module notes). Otherwise (``"mi_marginal"``):
    ``3 M - 2``, the calls it makes (module notes). One mode: 0. ``search`` is ``order_modes``'
    (``"exhaustive"`` or ``"screened"`` whatever the count of modes).
    """
    m = max(int(n_modes), 1)
    if m < 2:
        return 0  # one mode is Phi_ref itself: nothing is estimated
    if method != "mi_greedy":
        return 3 * m - 2  # every score, the cumulative MI and the swapped rivals
    if search == "exhaustive" or (search == "auto" and m <= _EXHAUSTIVE_MAX_MODES):
        return m * (m + 1) // 2 - 1
    tail = min(_EXHAUSTIVE_TAIL, m - 1)  # steps with 2..tail modes left score them all
    return m + tail * (tail + 1) // 2 - 1 + 2 * (m - 1 - tail)


def least_ordering_seconds(estimator: str, n_samples: int, n_modes: int,
                           n_resamples: int = 0, n_orderings: int = 1,
                           method: str = "mi_marginal", search: str = "auto"
                           ) -> tuple[float, int]:
    """Return (least CPU seconds, least number of MI estimates) of MI orderings.

    Parameters
    ----------
    estimator : str
        MI method name; another (an estimator object) costs 0 here (unknown).
    n_samples : int
        Samples per MI estimate (``min(budget, frames x pupil pixels)``).
    n_modes : int
        Modes ordered, M.
    n_resamples : int
        Bootstrap replicates of each ordering (``2 M - 2`` estimates each).
    n_orderings : int
        MI orderings run.
    method : str
        Ordering method (:func:`least_ordering_calls`): ``"mi_greedy"`` counts its
        search's estimates, any other ``3 M - 2``.
    search : str
        ``order_modes``' ``search`` (:func:`least_ordering_calls`).

    Returns
    -------
    seconds : float
        ``calls x (MI_SECONDS_PER_CALL + SCREEN_SECONDS_PER_CALL + n x
        (MI_SECONDS_PER_SAMPLE(n) + SCREEN_SECONDS_PER_SAMPLE)) + n_orderings x (1 +
        n_resamples) x M x n x GATHER_SECONDS_PER_ENTRY`` [s] (module notes).
    calls : int
        Least number of MI estimates.
    """
    rate = MI_SECONDS_PER_SAMPLE.get(estimator) if isinstance(estimator, str) else None
    replicates = max(n_resamples, 0)
    calls = n_orderings * (least_ordering_calls(n_modes, method, search)
                           + replicates * max(2 * n_modes - 2, 0))
    if rate is None or n_orderings < 1:
        return 0.0, calls
    n = n_samples
    per_call = (MI_SECONDS_PER_CALL[estimator] + SCREEN_SECONDS_PER_CALL
                + n * (rate(n) + SCREEN_SECONDS_PER_SAMPLE))
    gathers = n_orderings * (1 + replicates) * n_modes * n * GATHER_SECONDS_PER_ENTRY
    return calls * per_call + gathers, calls


#: this thread's run already judged as a whole (``judged_run``): its orderings are silent
_JUDGED = threading.local()


@contextlib.contextmanager
def judged_run() -> Iterator[None]:
    """Within: this thread's :func:`check_ordering_seconds` neither refuses nor warns.

    For ``ordering_stability``, which judges its whole run once and then calls
    ``order_modes`` per window and seed. Its ``catch_warnings`` block before filtered
    every thread's ``OrderingCostWarning`` for the run's length, and, outside the
    package's lock, left the filter installed for good (round 40 PART a, T25); a
    thread-local flag changes no process-wide state.
    """
    before = getattr(_JUDGED, "active", False)
    _JUDGED.active = True
    try:
        yield
    finally:
        _JUDGED.active = before


def seconds_text(seconds: float, above: float | None = None) -> str:
    """How the refusals and notes state an estimate: ``"is estimated at N s of CPU or more"``.

    :func:`least_ordering_seconds` is a lower bound; printed as "estimated at 8 s of CPU"
    it read as a forecast, where a 1000-mode ``mi_marginal`` ordering of 200,000 samples
    per estimate took 42.7 s (5.3x; 3.8x at 200 modes once compiled; adversarial round
    46 PART a, A03a / A03c, at load 9). Since fixes 47-b the bound is 1.1-4.6x below the
    CPU measured on the module notes' grid. The command line's notes say it in the same
    words.

    Whole seconds from 10 s, two significant figures below (``"2e-06 s"``, ``"0.35 s"``,
    ``"8.4 s"``): rounded to whole seconds, ``forecast --max-seconds 1e-9`` was refused
    as "estimated at 0 s of CPU or more ... more than --max-seconds=1e-09" (stop 56,
    fix49-c's left item).

    Parameters
    ----------
    seconds : float
        The estimate [CPU s].
    above : float, optional
        The limit a refusal says the estimate exceeds [s]: more significant figures
        (up to 17) until the printed estimate reads above it (8.4 s against 8.35 s).

    Returns
    -------
    str
        ``"is estimated at N s of CPU or more (a lower bound)"``.
    """
    digits = 2 if seconds < 10 else len(f"{seconds:.0f}")
    text = f"{seconds:.{digits}g}"
    while above is not None and seconds > above and float(text) <= above and digits < 17:
        digits += 1
        text = f"{seconds:.{digits}g}"
    return f"is estimated at {text} s of CPU or more (a lower bound)"


def check_ordering_seconds(seconds: float, what: str, how: str, max_seconds: float | None,
                           stacklevel: int = 2) -> None:
    """Refuse above ``max_seconds``, or warn above :data:`NOTE_ORDERING_SECONDS`, an estimate.

    The one rule of ``order_modes`` and ``ordering_stability`` (module notes).

    Parameters
    ----------
    seconds : float
        Estimated CPU seconds (:func:`least_ordering_seconds`).
    what : str
        What is estimated, ending with :func:`seconds_text`.
    how : str
        How to shorten it, in the caller's argument names.
    max_seconds : float or None
        Most seconds allowed; None: no limit.
    stacklevel : int
        ``warnings.warn``'s, counted from the caller of this function.

    Raises
    ------
    ValueError
        Above ``max_seconds``.
    """
    if getattr(_JUDGED, "active", False):
        return  # inside a run judged as a whole (judged_run)
    if seconds <= NOTE_ORDERING_SECONDS and (max_seconds is None or seconds <= max_seconds):
        return
    if max_seconds is not None and seconds > max_seconds:
        # the refusal's estimate reads above the limit it exceeds (fix50-b): ``what``
        # ends with seconds_text(seconds), said again with the digits that show it
        said = seconds_text(seconds)
        if what.endswith(said):
            what = what[: len(what) - len(said)] + seconds_text(seconds, above=max_seconds)
        raise ValueError(f"{what}, more than `max_seconds`={max_seconds:g}; {how}, or raise "
                         "`max_seconds` (None: no limit).")
    warn(f"{what}; {how}.", OrderingCostWarning, stacklevel=stacklevel + 1)
