"""The default estimators (KSG) on every "Beyond Normal" task of at most 2 x 2 dimensions.

Reference: the exact MI of each task (Czyz et al., NeurIPS 2023, regenerated in
``benchmarks/bench_mi_accuracy.py``; every truth is checked independently in
``test_beyond_normal_tasks.py``). The full table at n = 1e4 is in
``benchmarks/RESULTS.md`` (section "The KSG defaults"); this is its test-tier slice.

The defaults (``method=`` omitted: ``"ksg"`` for ``mutual_information`` and
``conditional_mutual_information`` since 2026-11-29) are asserted strictly against
issue 27's target, within max(0.05 nats, 10 %) of the truth, median of 3 seeds, on all
23 tasks of at most 2 x 2 dimensions: at n = 4000 where the default meets the target
there with a margin of at least 0.02 nats (measured: every 1 x 1 task and the
Gaussian 2 x 2 groups, errors -0.031 ... +0.017), at the target's own n = 1e4 for the
Student-t 2 x 2 groups, whose margin at 4000 is only 0.005-0.020 nats (errors -0.045,
-0.030 at 4000; -0.018, -0.008 at 1e4).

The ``ksg`` and ``gaussian`` methods are also asserted with a statistical tolerance:
the mean of 3 seeds must lie within ``0.01 + 4 sd / sqrt(3)`` of the truth, with sd the
standard deviation of one estimate at n = 4000 measured over 20 other seeds
(1000-1019) on the shared machine (``SD`` below) and 0.01 nats an allowance for the
estimators' finite-sample bias (largest measured mean error among these cases: +0.008
nats, ksg on ``bimodal-1x1``). The ``gaussian`` method is only asserted where the data
are jointly Gaussian (it is blind to non-linear dependence).

The former defaults, ``kde`` (MI) and ``histogram`` (CMI; still the default of the
paper's orderings, which name it), are options now: where they meet the target they
are asserted strictly; their known limits are non-strict xfails with the cause named.
"""

import importlib.util
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    conditional_mutual_information,
    mutual_information,
)

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


def estimate(task, method, seed, n=N, **options):
    """The public API with default options (unless given), as the benchmark calls it.

    A default that switches estimator with a ``BiasRuleWarning`` (the CMI histogram's
    resolution rule on 2 x 2 groups) is judged on the value it returns, as in the
    benchmark; the warning itself is tested in test_resolution_rule.py.
    """
    x, y, z = task.sample(np.random.default_rng(seed), n)
    if task.dx == task.dy == 1 and not task.dz:
        return mutual_information(x[:, 0], y[:, 0], method=method, **options)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BiasRuleWarning)
        return conditional_mutual_information(x, y, z, method=method, **options)


@pytest.mark.parametrize("name, method", sorted(SD))
def test_ksg_and_gaussian_defaults_recover_the_exact_mi(tasks, name, method):
    task = tasks[name]
    mean = float(np.mean([estimate(task, method, s) for s in SEEDS]))
    tol = BIAS_ALLOWANCE + 4 * SD[name, method] / math.sqrt(len(SEEDS))
    assert abs(mean - task.truth) <= tol, (name, method, mean, task.truth, tol)


def _meets_target(value, truth):
    return abs(value - truth) <= max(0.05, 0.1 * truth)


#: Tasks where the default needs the target's n = 1e4 (module docstring).
N_TARGET = 10_000
AT_TARGET_N = ("student-2x2-df1", "student-2x2-df2", "asinh-student-2x2-df1")
JUDGED = ("normal-1x1", "normal-cdf-1x1", "half-cube-1x1", "wiggly-1x1", "bimodal-1x1",
          "additive-0.1", "additive-0.75", "student-1x1-df1", "student-1x1-df2",
          "student-1x1-df3", "student-1x1-df5", "asinh-student-1x1-df1", "X-mixture-1x1",
          "cauchy-additive", "glitch-1", "outliers-1pct", "rounded-0.1", "rounded-0.5",
          "dense-2x2", "sparse-2x2", "student-2x2-df1", "student-2x2-df2",
          "asinh-student-2x2-df1")


def test_the_judged_tasks_are_every_task_of_at_most_2x2(tasks):
    small = sorted(t.name for t in tasks.values()
                   if t.dx <= 2 and t.dy <= 2 and not t.dz)
    assert small == sorted(JUDGED) and len(JUDGED) == 23


def default_estimate(task, seed, n):
    """The public API with ``method=`` omitted (the default), as a user calls it."""
    x, y, z = task.sample(np.random.default_rng(seed), n)
    if task.dx == task.dy == 1 and not task.dz:
        return mutual_information(x[:, 0], y[:, 0])
    return conditional_mutual_information(x, y, z)


@pytest.mark.parametrize("name", JUDGED)
def test_the_default_meets_the_issue_target(tasks, name):
    task = tasks[name]
    n = N_TARGET if name in AT_TARGET_N else N
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)  # no switch of method on these
        value = float(np.median([default_estimate(task, s, n) for s in SEEDS]))
    assert _meets_target(value, task.truth), (name, value, task.truth)


# issue 27's target (within 0.05 nats or 10 % at n = 1e4), asserted at this tier's n = 4000
# where the default meets it with a margin (median of 3 seeds, measured at n = 4000: kde
# glitch -0.018, Student-t df 1 -0.013, rounded to 0.5 sd -0.005 (discrete pairs: the
# Miller-Madow plug-in of their table), 1 % outliers -0.026; histogram glitch -0.015,
# Student-t df 1 -0.022, X mixture -0.027 with bins="auto" (8 samples per joint cell), which
# is an option, not the default: see test_histogram_auto_bins_meet_the_target).
@pytest.mark.parametrize("name, method", [("glitch-1", "kde"), ("glitch-1", "histogram"),
                                          ("student-1x1-df1", "kde"),
                                          ("rounded-0.5", "kde"), ("outliers-1pct", "kde")])
def test_kde_and_histogram_meet_the_issue_target(tasks, name, method):
    task = tasks[name]
    value = float(np.median([estimate(task, method, s) for s in SEEDS]))
    assert abs(value - task.truth) <= max(0.05, 0.1 * task.truth)


# Fixed by issue 27's second accuracy round for the former defaults, asserted at the
# target's n = 1e4 (median of 3 seeds, measured: kde Cauchy -0.064 with the
# cross-validated bandwidth, -0.097 with Scott's (at n = 4000: -0.102, which is why this
# n); sparse 2 x 2 through the CMI histogram's resolution rule, switched to the KSG CMI:
# +0.000, before -0.185). The Student-t 2 x 2 groups take that switch too, which returns
# the KSG CMI bit for bit (test_resolution_rule.py): the default's test above covers them.
@pytest.mark.parametrize("name, method", [("cauchy-additive", "kde"),
                                          ("sparse-2x2", "histogram")])
def test_former_defaults_meet_the_issue_target_at_its_n(tasks, name, method):
    task = tasks[name]
    value = float(np.median([estimate(task, method, s, n=N_TARGET) for s in SEEDS]))
    assert abs(value - task.truth) <= max(0.05, 0.1 * task.truth)


@pytest.mark.parametrize("name", ["student-1x1-df1", "X-mixture-1x1"])
def test_histogram_auto_bins_meet_the_target(tasks, name):
    task = tasks[name]
    value = float(np.median([estimate(task, "histogram", s, bins="auto") for s in SEEDS]))
    assert abs(value - task.truth) <= max(0.05, 0.1 * task.truth)


# The known limits of the non-default estimators, each with its cause (benchmarks/RESULTS.md,
# 'MI accuracy (Beyond Normal tasks)', 'After the accuracy round', 'The KSG defaults');
# measured at n = 4000, median of 3 seeds. The default (KSG) meets each of these tasks.
CAUSES = {
    ("cauchy-additive", "histogram"): "the copula of (x, x + Cauchy) is a ridge narrowing "
    "into its corners, thinner than the equiprobable cells there: -0.259 (n = 1e4, "
    "Hacine-Gharbi's ~22 bins: -0.207; bins='auto', 35 bins: -0.143; KSG -0.005)",
    ("student-1x1-df1", "histogram"): "the default Hacine-Gharbi bins, derived for a "
    "Gaussian pair, are too few for the Student-t copula's tails at this n: -0.061 (at "
    "the target's n = 1e4: -0.043, within it; bins='auto' meets it, above; not the default "
    "because of its larger spread, histogram module notes)",
    ("X-mixture-1x1", "histogram"): "the default Hacine-Gharbi rule keeps 16 bins at a rank "
    "correlation ~0 and misses the X's thin arms: -0.077 (n = 1e4: -0.057; bins='auto' "
    "meets it, above)",
    ("outliers-1pct", "histogram"): "discretisation bias of the equiprobable bins: -0.081 "
    "(n = 1e4: -0.071; bins='auto', 35 bins: -0.047)",
    ("student-2x2-df1", "kde"): "the 4-D conditional KDE on normal scores smooths away the "
    "Student-t copula's tail dependence at every bandwidth: -0.100 (n = 1e4: -0.072 at "
    "Scott's h; a common h of 0.6, 0.8, 1.3, 1.6, 2.0 x Scott's: -0.135, -0.073, -0.100, "
    "-0.137, -0.187; each entropy at its own cross-validated h: -0.085; Abramson's "
    "sample-point bandwidth, 1 seed: -0.081)",
}
@pytest.mark.parametrize("name, method", [pytest.param(*key, marks=pytest.mark.xfail(
    strict=False, reason=f"known limit of method={key[1]!r} (not the default): {cause}"))
    for key, cause in CAUSES.items()])
def test_known_limits_of_the_non_default_estimators(tasks, name, method):
    task = tasks[name]
    value = float(np.median([estimate(task, method, s) for s in SEEDS]))
    assert abs(value - task.truth) <= max(0.05, 0.1 * task.truth)
