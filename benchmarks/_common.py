"""What the benchmark scripts share: integer options, median timings, the AR(1) test log.

Imported by a script run as ``python benchmarks/bench_*.py`` (its folder is then first
on ``sys.path``). The numbers keep their meaning: each script still says which clock it
reads (``cpu``: this process's CPU time, ``time.process_time``, what the shared
machine's load does not inflate; otherwise wall time, ``time.perf_counter``) and
whether a first call is left out of the timings (``warm``: imports, caches, numba).
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from typing import Any

import numpy as np


def int_options(doc: str, **defaults: int) -> argparse.ArgumentParser:
    """A parser described by ``doc``'s first line with an ``int`` option per default.

    ``frames=200`` gives ``--frames`` (default 200); an underscore reads as a dash
    (``imaging_repeats`` gives ``--imaging-repeats``). Add further options to the result.
    """
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    for name, default in defaults.items():
        parser.add_argument("--" + name.replace("_", "-"), type=int, default=default)
    return parser


def timed(fn: Callable[[], Any], repeats: int, *, cpu: bool = False,
          warm: bool = True) -> tuple[float, Any]:
    """Median time of ``fn()`` over ``repeats`` calls [s], and its last result.

    Parameters
    ----------
    fn : callable
        Called without arguments.
    repeats : int
        Timed calls (>= 1).
    cpu : bool
        CPU time of this process (``time.process_time``) rather than wall time.
    warm : bool
        Call ``fn`` once, untimed, first.

    Returns
    -------
    tuple
        ``(median seconds, result of the last call)``.
    """
    clock = time.process_time if cpu else time.perf_counter
    if warm:
        fn()
    times, out = [], None
    for _ in range(repeats):
        t0 = clock()
        out = fn()
        times.append(clock() - t0)
    return float(np.median(times)), out


def median_time(fn: Callable[[], Any], repeats: int) -> float:
    """Median wall time of ``fn()`` [s] after one untimed call (:func:`timed`)."""
    return timed(fn, repeats)[0]


def cpu_median(fn: Callable[[], Any], repeats: int) -> float:
    """Median CPU time of ``fn()`` [s] after one untimed call (:func:`timed`)."""
    return timed(fn, repeats, cpu=True)[0]


def ar1_log(frames: int, modes: int, seed: int, rho: float = 0.9) -> np.ndarray:
    """``(frames, modes)`` AR(1) series ``x_t = rho x_(t-1) + e_t``, unit Gaussian ``e``."""
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((frames, modes))
    for t in range(1, frames):
        x[t] += rho * x[t - 1]
    return x


def clopper_pearson(k: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Exact (Clopper-Pearson) binomial interval of a coverage of ``k`` hits in ``n``."""
    from scipy import stats

    tail = 0.5 * (1.0 - level)
    low = stats.beta.ppf(tail, k, n - k + 1) if k > 0 else 0.0
    high = stats.beta.ppf(1.0 - tail, k + 1, n - k) if k < n else 1.0
    return float(low), float(high)


def ar1_lag_pair(phi: float, frames: int, seed: int) -> tuple:
    """``(data, r, gain)`` of one seeded AR(1) log: columns x[t+1], x[t], their correlation
    and Gaussian gain -0.5 ln(1 - r^2) [nats] (the select coverage benches' draw: 500
    frames of burn-in from ``default_rng(seed)``)."""
    import math

    e = np.random.default_rng(seed).standard_normal(frames + 500)
    x = np.empty_like(e)
    x[0] = e[0]
    for t in range(1, e.size):
        x[t] = phi * x[t - 1] + e[t]
    x = x[500:]
    data = np.column_stack([x[1:], x[:-1]])
    r = np.corrcoef(data.T)[0, 1]
    return data, r, -0.5 * math.log(1 - r * r)
