"""Default estimators on a handful of "Beyond Normal" tasks (issue 27, item 2).

Reference: the exact MI of each task (Czyz et al., NeurIPS 2023, regenerated in
``benchmarks/bench_mi_accuracy.py``; every truth is checked independently in
``test_beyond_normal_tasks.py``). The full table at n = 1e4 is in
``benchmarks/RESULTS.md``; this is its test-tier slice at n = 4000.

Only the ``ksg`` and ``gaussian`` methods are asserted, with DEFAULT options: their
defaults are not being changed by issue 27, while the ``kde`` and ``histogram``
defaults are (rank / copula inputs, quantile bins), so their checks, against the
issue's target (within max(0.05 nats, 10 %)), are marked non-strict xfail until then.

Tolerance: the mean of 3 seeds must lie within ``0.01 + 4 sd / sqrt(3)`` of the
truth, with sd the standard deviation of one estimate at n = 4000 measured over 20
other seeds (1000-1019) on the shared machine (``SD`` below) and 0.01 nats an
allowance for the estimators' finite-sample bias (largest measured mean error among
these cases: +0.008 nats, ksg on ``bimodal-1x1``). The ``gaussian`` method is only
asserted where the data are jointly Gaussian (it is blind to non-linear dependence).
"""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from modalinfo.information import conditional_mutual_information, mutual_information

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_mi_accuracy.py"
N = 4000
SEEDS = (0, 1, 2)

# sd of one estimate at n = 4000 [nats], 20 seeds (measured; see module docstring)
SD = {
    ("normal-1x1", "ksg"): 0.0148, ("normal-1x1", "gaussian"): 0.0091,
    ("half-cube-1x1", "ksg"): 0.0158, ("wiggly-1x1", "ksg"): 0.0134,
    ("bimodal-1x1", "ksg"): 0.0150, ("X-mixture-1x1", "ksg"): 0.0173,
    ("asinh-student-1x1-df1", "ksg"): 0.0201, ("additive-0.75", "ksg"): 0.0181,
    ("rounded-0.1", "ksg"): 0.0128, ("rounded-0.1", "gaussian"): 0.0092,
    ("sparse-2x2", "ksg"): 0.0226, ("sparse-2x2", "gaussian"): 0.0180,
    ("dense-2x2", "ksg"): 0.0122, ("dense-2x2", "gaussian"): 0.0096,
    ("cmi-dz2", "ksg"): 0.0144, ("cmi-dz2", "gaussian"): 0.0105,
    ("cmi-null-dz5", "ksg"): 0.0055, ("cmi-null-dz5", "gaussian"): 0.0002,
}
BIAS_ALLOWANCE = 0.01


@pytest.fixture(scope="module")
def tasks():
    spec = importlib.util.spec_from_file_location("bench_mi_accuracy", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.build_tasks()


def estimate(task, method, seed):
    """The public API with default options, as the benchmark calls it."""
    x, y, z = task.sample(np.random.default_rng(seed), N)
    if task.dx == task.dy == 1 and not task.dz:
        return mutual_information(x[:, 0], y[:, 0], method=method)
    return conditional_mutual_information(x, y, z, method=method)


@pytest.mark.parametrize("name, method", sorted(SD))
def test_ksg_and_gaussian_defaults_recover_the_exact_mi(tasks, name, method):
    task = tasks[name]
    mean = float(np.mean([estimate(task, method, s) for s in SEEDS]))
    tol = BIAS_ALLOWANCE + 4 * SD[name, method] / math.sqrt(len(SEEDS))
    assert abs(mean - task.truth) <= tol, (name, method, mean, task.truth, tol)


# issue 27's target (within 0.05 nats or 10 % at n = 1e4). The rank-based defaults meet it
# on one glitch and on Student-t df 1 with kde; the histogram on Student-t df 1 and both
# on the Cauchy pair still miss it (benchmarks/RESULTS.md, 'MI accuracy (Beyond Normal
# tasks)': the rank-transformed ridge is narrower than the kernel / the bins resolve).
ISSUE_27_OPEN = pytest.mark.xfail(
    strict=False, reason="issue 27 (open): rank-based kde/histogram miss heavy-tail tasks "
                         "by 0.09-0.19 nats at n = 1e4")


@pytest.mark.parametrize("name, method", [("glitch-1", "kde"), ("glitch-1", "histogram"),
                                          ("student-1x1-df1", "kde")])
def test_kde_and_histogram_defaults_meet_the_issue_target(tasks, name, method):
    task = tasks[name]
    value = float(np.median([estimate(task, method, s) for s in SEEDS]))
    assert abs(value - task.truth) <= max(0.05, 0.1 * task.truth)


@ISSUE_27_OPEN
@pytest.mark.parametrize("name, method", [("student-1x1-df1", "histogram"),
                                          ("cauchy-additive", "kde"),
                                          ("cauchy-additive", "histogram")])
def test_kde_and_histogram_heavy_tail_misses(tasks, name, method):
    task = tasks[name]
    value = float(np.median([estimate(task, method, s) for s in SEEDS]))
    assert abs(value - task.truth) <= max(0.05, 0.1 * task.truth)
