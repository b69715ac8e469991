"""What the benchmark scripts share: integer options, median timings, the AR(1) test logs.

Imported by a script run as ``python benchmarks/bench_*.py`` (its folder is then first
on ``sys.path``). The numbers keep their meaning: each script still says which clock it
reads (``cpu``: this process's CPU time, ``time.process_time``, what the shared
machine's load does not inflate; otherwise wall time, ``time.perf_counter``) and
whether a first call is left out of the timings (``warm``: imports, caches, numba).
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable, Iterator
from pathlib import Path
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
    e = np.random.default_rng(seed).standard_normal(frames + 500)
    x = np.empty_like(e)
    x[0] = e[0]
    for t in range(1, e.size):
        x[t] = phi * x[t - 1] + e[t]
    x = x[500:]
    data = np.column_stack([x[1:], x[:-1]])
    r = np.corrcoef(data.T)[0, 1]
    return data, r, -0.5 * math.log(1 - r * r)


#: The clean log families a log-content rule is calibrated on (bench_layout_left31,
#: bench_pair_order_34b): each mode's AR(1) coefficient per :func:`family_rhos`.
FAMILIES = ("noll rho0 .5-.999", "one rho .5-.999", "rho 0.999", "rho -0.5", "white")


def radial_orders(m: int) -> np.ndarray:
    """Noll radial order of modes Z2.. (m of them)."""
    j = np.arange(2, m + 2)
    return np.floor((np.sqrt(8 * j - 7) - 1) / 2).astype(int)


def ar_log(shape: tuple[int, int], rhos: np.ndarray, sd: np.ndarray,
           rng: np.random.Generator) -> np.ndarray:
    """Stationary AR(1) columns (each started from its stationary law)."""
    from scipy.signal import lfilter

    t, m = shape
    e = rng.standard_normal((t, m))
    x = np.empty((t, m))
    for k in range(m):
        r = float(rhos[k])
        z = e[:, k] * math.sqrt(1 - r * r)
        z[0] = e[0, k]
        x[:, k] = lfilter([1.0], [1.0, -r], z)
    return x * sd


def family_rhos(family: str, m: int, rng: np.random.Generator) -> np.ndarray:
    """Each mode's AR(1) coefficient in one log of ``family`` (one of :data:`FAMILIES`)."""
    if family == "noll rho0 .5-.999":
        return rng.uniform(0.5, 0.999) ** (radial_orders(m) + 1.0)
    if family == "one rho .5-.999":
        return np.full(m, rng.uniform(0.5, 0.999))
    if family == "rho -0.5":
        return np.full(m, -0.5)
    return np.full(m, 0.999 if family == "rho 0.999" else 0.0)


def _family_logs(shape: tuple[int, int], family: str, logs: int,
                 rng: np.random.Generator) -> Iterator[np.ndarray]:
    """``logs`` logs of ``family``, drawn one at a time from ``rng``."""
    sd = (radial_orders(shape[1]) + 1.0) ** (-11.0 / 6.0)  # Noll-like, falling with order
    for _ in range(logs):
        yield ar_log(shape, family_rhos(family, shape[1], rng), sd, rng)


def clean_logs(shapes, logs: int,
               rng: np.random.Generator) -> Iterator[tuple[str, tuple, Iterator[np.ndarray]]]:
    """Yield ``(name, shape, logs)`` rows of clean ``(frames, modes)`` logs, in order.

    Per shape, ``logs`` seeded stationary AR(1) logs of each of :data:`FAMILIES` (standard
    deviations ``(n + 1) ** (-11 / 6)``, ``n`` the Noll radial order), drawn from ``rng``
    as the row is read (read each row before the next); then ``kaos_like`` open- and
    closed-loop logs (4,000 x 27, seeds 0-4) and the shipped logs of data/.
    """
    for shape in shapes:
        for family in FAMILIES:
            yield family, shape, _family_logs(shape, family, logs, rng)
    from modalinfo.io import load
    from modalinfo.telemetry.synthetic import kaos_like

    for closed in (False, True):
        yield ("kaos_like " + ("closed" if closed else "open"), (4000, 27),
               (kaos_like(4000, closed_loop=closed, seed=seed).coeffs for seed in range(5)))
    root = Path(__file__).resolve().parent.parent / "data"
    for path in sorted(root.glob("*.npz")):
        coeffs = np.asarray(load(path).coeffs)
        yield path.name, coeffs.shape, iter([coeffs])
