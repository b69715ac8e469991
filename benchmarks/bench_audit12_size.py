"""Size and coverage of the package's statistical claims on AO-like nulls (audit 12-tests).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_audit12_size.py CLAIM DRAWS N [KINDS]

CLAIM is one of ``mi_shuffle`` (:func:`modalinfo.information.mutual_information_permutation_test`,
default ``permutation="shuffle"``, Gaussian estimator, 99 permutations), ``mi_circular``
(the same, ``permutation="circular"``), ``mi_default_hist`` (the default histogram
estimator, shuffle), ``cmi_zK`` (:func:`modalinfo.information.conditional_mutual_information_test`
of x = e1 + s, y = e2 + s given Z (K columns, s = sum(Z) / sqrt(K)): x and y independent
given Z; Gaussian estimator, 99 circular surrogates), ``mi_ci`` (coverage of the 95 %
:func:`modalinfo.information.mutual_information_ci`, Gaussian, 199 block-bootstrap
resamples, of the exact -0.5 ln(1 - 0.36) for rho = 0.6), ``cmi_ci`` (the same of
:func:`modalinfo.information.conditional_mutual_information_ci` of x = e1 + z,
y = 0.6 e1 + 0.8 e2 + z given z, partial correlation 0.6; left13-stats) and ``dm`` (the one-sided
Diebold-Mariano test of ``modalinfo.forecast.evaluate`` on the loss differential
e1^2 - e2^2 of two equally good forecasts, h = 1); ``dm_before`` the same with the test
before left12-dm (``dm_before`` below), ``dm_power`` / ``dm_power_before`` their rejection
rates when the second forecast's MSE is 5 % smaller (d = 0.95 e2^2 - e1^2; power).

KINDS (comma-separated; every series of one draw independent and of one kind): ``iid``
Gaussian; ``ar1_R`` stationary AR(1) of coefficient R (0.9, 0.95, 0.99, 0.999); ``ar2_50Hz``
AR(2) with a 50 Hz resonance at 2 kHz (pole radius 0.99); ``t3`` AR(1) 0.9 with Student
t3 innovations; ``varstep`` AR(1) 0.9 whose innovations' variance steps x4 halfway;
``trend`` AR(1) 0.9 plus a linear trend of 3 innovation sd; ``int16`` AR(1) 0.9 x 3
rounded to integers (ADU-like); ``smooth`` white noise through a Gaussian of sd 10 frames
(lag-1 autocorrelation ~0.999, correlation time ~20 frames; left14-dm). Draw k of kind i
uses ``default_rng([i, k])``.

A rate is the share of draws with p <= alpha (size, under a true null) or whose interval
holds the exact value (coverage); its binomial standard error is sqrt(a (1 - a) / DRAWS)
(1.5 % at a = 0.05 and 200 draws). Table: docs/ADVERSARIAL.md, "Audit 12-tests".
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import math  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402
from scipy.ndimage import gaussian_filter1d  # noqa: E402
from scipy.signal import lfilter  # noqa: E402

KINDS = ["iid", "ar1_0.9", "ar1_0.99", "ar1_0.999", "ar2_50Hz", "t3", "varstep", "trend",
         "int16", "ar1_0.95", "smooth"]


def ar1(phi: float, n: int, rng: np.random.Generator, innov=None) -> np.ndarray:
    """Stationary AR(1): x_t = phi x_(t-1) + e_t (unit Gaussian e unless given)."""
    e = rng.standard_normal(n) if innov is None else innov
    x0 = rng.standard_normal() / math.sqrt(1 - phi * phi)
    return lfilter([1.0], [1.0, -phi], e, zi=[phi * x0])[0]


def ar2(n: int, rng: np.random.Generator) -> np.ndarray:
    """AR(2) with a 50 Hz resonance at 2 kHz (pole radius 0.99), 2000 frames burnt in."""
    r, f = 0.99, 50 / 2000
    a1, a2 = 2 * r * math.cos(2 * math.pi * f), -r * r
    return lfilter([1.0], [1.0, -a1, -a2], rng.standard_normal(n + 2000))[2000:]


def gen(kind: str, n: int, rng: np.random.Generator) -> np.ndarray:
    """One series of the kind (see the module notes)."""
    if kind == "iid":
        return rng.standard_normal(n)
    if kind.startswith("ar1_"):
        return ar1(float(kind[4:]), n, rng)
    if kind == "ar2_50Hz":
        return ar2(n, rng)
    if kind == "t3":
        return ar1(0.9, n, rng, rng.standard_t(3, n))
    if kind == "varstep":
        e = rng.standard_normal(n)
        e[n // 2:] *= 2.0
        return ar1(0.9, n, rng, e)
    if kind == "trend":
        return ar1(0.9, n, rng) + np.linspace(0, 3, n)
    if kind == "int16":
        return np.round(ar1(0.9, n, rng) * 3.0)
    if kind == "smooth":  # left14-dm: tests/forecast/test_dm_size_left12.py's smooth noise
        return gaussian_filter1d(rng.standard_normal(n + 200), 10.0)[100:-100]
    raise ValueError(kind)


def dm_before(d: np.ndarray, h: int) -> float:
    """p-value of the DM test before left12-dm (commit 5bee73d), for the before columns.

    The larger of the Bartlett (lag ``max(h - 1, floor(4 (N/100)^(2/9)))``) and
    rectangular (lag ``h - 1``) long-run variances, HLN's factor, t with N - 1 dof.
    """
    from scipy.stats import t as student_t

    n = d.size
    dc = d - d.mean()
    lag = max(h - 1, int(np.floor(4 * (n / 100.0) ** (2.0 / 9.0))))
    acov = [float(dc[k:] @ dc[:n - k]) / n for k in range(lag + 1)]
    nw = acov[0] + 2 * sum((1 - k / (lag + 1.0)) * acov[k] for k in range(1, lag + 1))
    unif = acov[0] + 2 * sum(acov[1:h])
    var = max(nw, unif, 0.0)
    hln = math.sqrt(max(n - h, 0) * max(n - h + 1.0, 0.0)) / n
    stat = 0.0 if d.mean() == 0.0 else d.mean() / math.sqrt(var / n) * hln
    return float(student_t.cdf(stat, n - 1))


def one(claim: str, kind: str, k: int, n: int) -> float | bool:
    """p-value (tests) or coverage (intervals) of draw k."""
    from modalinfo.forecast.evaluate import _dm_test
    from modalinfo.information import (
        conditional_mutual_information_ci,
        conditional_mutual_information_test,
        mutual_information_ci,
        mutual_information_permutation_test,
    )
    rng = np.random.default_rng([KINDS.index(kind), k])
    x, y = gen(kind, n, rng), gen(kind, n, rng)
    if claim == "mi_shuffle":
        return mutual_information_permutation_test(x, y, "gaussian", n_permutations=99,
                                                   seed=k).pvalue
    if claim == "mi_circular":
        return mutual_information_permutation_test(x, y, "gaussian", n_permutations=99,
                                                   permutation="circular", seed=k).pvalue
    if claim == "mi_default_hist":
        return mutual_information_permutation_test(x, y, n_permutations=99, seed=k).pvalue
    if claim.startswith("cmi_z"):
        dz = int(claim[5:])
        z = np.column_stack([gen(kind, n, rng) for _ in range(dz)])
        s = z.sum(1) / math.sqrt(dz)
        return conditional_mutual_information_test(x + s, y + s, z, method="gaussian",
                                                   n_surrogates=99, seed=k).pvalue
    if claim == "mi_ci":
        rho = 0.6
        r = mutual_information_ci(x, rho * x + math.sqrt(1 - rho**2) * y, "gaussian",
                                  n_resamples=199, seed=k)
        return bool(r.low <= -0.5 * math.log(1 - rho**2) <= r.high)
    if claim == "cmi_ci":  # left13-stats: x = e1 + z, y = rho e1 + sqrt(1 - rho^2) e2 + z
        rho = 0.6
        z = gen(kind, n, rng)
        r = conditional_mutual_information_ci(
            x + z, rho * x + math.sqrt(1 - rho**2) * y + z, z, method="gaussian",
            n_resamples=199, seed=k)
        return bool(r.low <= -0.5 * math.log(1 - rho**2) <= r.high)
    if claim == "dm":
        return _dm_test(x**2 - y**2, 1)[1]
    if claim == "dm_before":
        return dm_before(x**2 - y**2, 1)
    if claim == "dm_power":  # the second forecast's MSE is 5 % smaller: a true skill
        return _dm_test(0.95 * y**2 - x**2, 1)[1]
    if claim == "dm_power_before":
        return dm_before(0.95 * y**2 - x**2, 1)
    raise ValueError(claim)


def main(argv: list[str]) -> None:
    claim, draws, n = argv[0], int(argv[1]), int(argv[2])
    for kind in (argv[3].split(",") if len(argv) > 3 else KINDS):
        t0 = time.process_time()
        values, warned = [], 0
        for k in range(draws):
            with warnings.catch_warnings(record=True) as w:
                warnings.simplefilter("always")
                values.append(one(claim, kind, k, n))
            warned += bool(w)
        v = np.array(values, dtype=float)
        cpu = time.process_time() - t0
        if claim in ("mi_ci", "cmi_ci"):
            print(f"{claim} {kind} n={n} coverage95={v.mean():.3f} "
                  f"warned={warned}/{draws} cpu={cpu:.0f}s", flush=True)
        else:
            # a NaN p-value (no honest test: the DM claims' too persistent differentials)
            # is no rejection; "untested" counts them
            print(f"{claim} {kind} n={n} size5={np.mean(v <= 0.05):.3f} "
                  f"size10={np.mean(v <= 0.10):.3f} untested={np.isnan(v).sum()}/{draws} "
                  f"warned={warned}/{draws} cpu={cpu:.0f}s", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
