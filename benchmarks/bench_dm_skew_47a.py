"""Candidate fixes of the DM test's skew on persistent-volatility differentials (issue 27, fix47-a).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_dm_skew_47a.py DRAWS [evaluate]

Round 46 PART a P39-P43: two forecasts equal in MSE on an AR(1) mode of coefficient phi
(``(2 phi - 1) x_t`` against persistence) have the loss differential
``d_t = 4 (1 - phi) x_t e_(t+1)``, a martingale difference whose volatility ``x_t^2`` is
persistent. Each candidate gives a one-sided p-value (``d < 0`` favours the predictor) on
the same draws (``mds phi``; ``gauss phi``: a Gaussian AR(1) differential, the module
notes' homoskedastic nulls; ``power phi``: the optimal forecast ``phi x_t`` against
persistence, a real difference):

- ``ours``: ``modalinfo.forecast.evaluate._dm_test`` (EWC, B by the AR plug-in, t_B);
- ``wild``: wild bootstrap of the same EWC t ratio (same B), ``(d_t - mean) w_t`` with
  Rademacher weights (keeps the volatility path), 199 resamples;
- ``mbb``: moving-block bootstrap of the same t ratio, blocks of 25, 199 resamples;
- ``sn``: Lobato's (2001) self-normalised ratio ``sqrt(N) mean / sqrt(N^-2 sum S_t^2)``
  (``S_t`` partial sums of ``d - mean``), its fixed-b law tabulated from 20,000 Brownian
  paths of 2,000 steps;
- ``band``: ``_dm_terms`` with LLSW's cap ``0.4 N^(2/3)`` lifted: when LLSW's B passes the
  plug-in, B extends to ``N - 1`` (the ordinary variance, by Parseval) while every longer B
  passes too (``_dm_terms``' source patched at run time, ``band_terms``).

Columns: rejections at a nominal 5 % in the lower tail / the upper tail (binomial sd
``sqrt(0.0475 / DRAWS)``), and the bootstraps' milliseconds per differential. The
resamples use ``default_rng(0)`` (deterministic). Draw k of case i: ``default_rng([47, i,
k])``.

``evaluate``: the same through :func:`modalinfo.forecast.evaluate` (one predictor, h = 1,
train 0.5, seeds 9000 + k as in round 46's scripts), with the DM test as shipped and with
``band`` (``_dm_terms`` replaced in the module): P43 (phi 0.9, 500 origins), P39 (0.9,
2000), P40 (0.99, 2000) with ``(2 phi - 1) x_t``; power: ``phi x_t`` (DRAWS / 3 draws).
Columns: raw p < 5 % and ``beats_baseline`` (the flagged-pair rule included).
Table: benchmarks/RESULTS.md, rows "fix47-a".
"""

from __future__ import annotations

import inspect
import math
import sys
import time

import numpy as np
from scipy.fft import dct
from scipy.signal import lfilter
from scipy.stats import t as student_t

import modalinfo.forecast.evaluate  # noqa: F401  (the module, not the function)

EV = sys.modules["modalinfo.forecast.evaluate"]
RESAMPLES = 199
BLOCK = 25


def band_terms():
    """``_dm_terms`` with the flat-spectrum band extended beyond LLSW's cap."""
    src = inspect.getsource(EV._dm_terms).replace("def _dm_terms(", "def _band_terms(")
    edits = [
        ("    scale = float(np.max(np.abs(d - d.mean())))\n    if scale == 0.0:\n"
         "        return b_max, float(n)\n",
         "    b_band = max(b_max, n - 1)\n    scale = float(np.max(np.abs(d - d.mean())))\n"
         "    if scale == 0.0:\n        return b_band, float(n)\n"),
        ("    j = np.arange(0, b_max + 1)\n", "    j = np.arange(0, b_band + 1)\n"),
        ("        return b_max, n_eff\n", "        return b_band, n_eff\n"),
        ("    ok = lower >= 1.0 - _DM_SHORTFALL\n",
         "    ok = lower >= 1.0 - _DM_SHORTFALL\n    if ok[b_max - 1]:\n"
         "        fail = np.flatnonzero(~ok[b_max:])\n"
         "        return (b_max + int(fail[0]) if fail.size else b_band), n_eff\n"
         "    ok = ok[:b_max]\n"),
        ("        return int(j[1:][ok].max()), n_eff\n",
         "        return int(j[1:b_max + 1][ok].max()), n_eff\n"),
    ]
    for old, new in edits:
        if old not in src:
            raise SystemExit("bench_dm_skew_47a: _dm_terms changed; update the band patch")
        src = src.replace(old, new)
    space = dict(vars(EV))
    exec(src, space)  # noqa: S102  (the package's own source, patched above)
    return space["_band_terms"]


def ewc_t(d: np.ndarray, b: int) -> np.ndarray:
    """EWC t ratio of each row of ``d`` with ``b`` cosine terms."""
    n = d.shape[-1]
    lam = dct(d, type=2, axis=-1)[..., 1 : b + 1] / math.sqrt(2.0 * n)
    return d.mean(-1) / np.sqrt((lam**2).mean(-1) / n)


def sn_law() -> np.ndarray:
    """Sorted draws of ``W(1) / sqrt(int (W(r) - r W(1))^2 dr)`` (Lobato 2001)."""
    rng = np.random.default_rng(1)
    out = []
    for _ in range(10):
        w = rng.standard_normal((2000, 2000)).cumsum(1) / math.sqrt(2000)
        bridge = w - np.arange(1, 2001) / 2000 * w[:, -1:]
        out.append(w[:, -1] / np.sqrt((bridge**2).mean(1)))
    return np.sort(np.concatenate(out))


def draw(rng: np.random.Generator, kind: str, phi: float, n: int) -> np.ndarray:
    e = rng.standard_normal(n + 1001)
    x = lfilter([1.0], [1.0, -phi], e)[1000:]
    if kind == "mds":  # (2 phi - 1) x_t against x_t: equal MSE
        return 4.0 * (1.0 - phi) * x[:-1] * e[1001:]
    if kind == "power":  # phi x_t against x_t
        return (x[1:] - phi * x[:-1]) ** 2 - (x[1:] - x[:-1]) ** 2
    return x[:-1]


def pvalues(d, band, law, timing):
    n = d.size
    stat, p, b, _ = EV._dm_test(d, 1)
    out = {"ours": p}
    c = d - d.mean()
    if b > 0:
        t0 = time.perf_counter()
        w = np.random.default_rng(0).choice([-1.0, 1.0], size=(RESAMPLES, n))
        out["wild"] = (1 + np.sum(ewc_t(w * c, b) <= stat)) / (RESAMPLES + 1)
        timing["wild"] += time.perf_counter() - t0
        t0 = time.perf_counter()
        starts = np.random.default_rng(0).integers(0, n - BLOCK + 1,
                                                   size=(RESAMPLES, -(-n // BLOCK)))
        idx = (starts[:, :, None] + np.arange(BLOCK)).reshape(RESAMPLES, -1)[:, :n]
        out["mbb"] = (1 + np.sum(ewc_t(c[idx], b) <= stat)) / (RESAMPLES + 1)
        timing["mbb"] += time.perf_counter() - t0
    else:
        out["wild"] = out["mbb"] = math.nan
    s = np.cumsum(c)
    out["sn"] = np.searchsorted(law, math.sqrt(n) * d.mean() / math.sqrt(s @ s / n**2)) \
        / law.size
    bb = band(d)[0]
    out["band"] = float(student_t.cdf(ewc_t(d, bb), bb)) if bb > 0 else math.nan
    return out


def main(draws: int) -> None:
    band, law = band_terms(), sn_law()
    names = ("ours", "wild", "mbb", "sn", "band")
    cases = (("mds", 0.9, 500), ("mds", 0.9, 2000), ("mds", 0.99, 500), ("mds", 0.99, 2000),
             ("gauss", 0.0, 500), ("gauss", 0.9, 500), ("gauss", 0.99, 2000),
             ("power", 0.95, 1000), ("power", 0.99, 2000))
    print("| d | N | draws | " + " | ".join(names) + " | wild / mbb ms |")
    print("|---|---|---|" + "---|" * len(names) + "---|")
    for i, (kind, phi, n) in enumerate(cases):
        timing = {"wild": 0.0, "mbb": 0.0}
        ps = {k: np.empty(draws) for k in names}
        for k in range(draws):
            got = pvalues(draw(np.random.default_rng([47, i, k]), kind, phi, n), band, law,
                          timing)
            for name in names:
                ps[name][k] = got[name]
        cells = [f"{np.mean(np.nan_to_num(ps[m], nan=1.0) < .05):.3f} / "
                 f"{np.mean(np.nan_to_num(ps[m], nan=0.0) > .95):.3f}" for m in names]
        print(f"| {kind} {phi} | {n} | {draws} | " + " | ".join(cells)
              + f" | {1e3 * timing['wild'] / draws:.1f} / {1e3 * timing['mbb'] / draws:.1f} |",
              flush=True)
    print(f"(2 binomial sd at 5 %: {2 * math.sqrt(.0475 / draws):.3f})")


def through_evaluate(draws: int) -> None:
    import warnings

    from modalinfo.forecast import LinearPredictor, evaluate

    shipped = EV._dm_terms
    print("| case | phi | origins | draws | raw 5 % shipped | beats shipped | raw 5 % band | "
          "beats band |")
    print("|---|---|---|---|---|---|---|---|")
    for case, phi, frames, opt in (("P43", 0.9, 1000, False), ("P39", 0.9, 4000, False),
                                   ("P40", 0.99, 4000, False), ("power", 0.95, 2000, True),
                                   ("power", 0.99, 4000, True)):
        reps = max(1, draws // 3) if opt else draws
        cells = []
        for terms in (shipped, band_terms()):
            EV._dm_terms = terms
            rows = []
            for k in range(reps):
                e = np.random.default_rng(9000 + k).normal(size=frames + 1000)
                x = lfilter([1.0], [1.0, -phi], e)[1000:]
                pred = LinearPredictor(a=phi if opt else 2 * phi - 1, b=0.0)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = evaluate({"c": pred}, x, train=0.5, horizons=[1])
                rows.append((r.pvalue[2, 0], r.beats_baseline[2, 0]))
            a = np.nan_to_num(np.array(rows, dtype=float), nan=1.0)
            cells += [f"{np.mean(a[:, 0] < .05):.3f}", f"{a[:, 1].mean():.3f}"]
        EV._dm_terms = shipped
        print(f"| {case} | {phi} | {frames // 2} | {reps} | " + " | ".join(cells) + " |",
              flush=True)


if __name__ == "__main__":
    if sys.argv[2:] == ["evaluate"]:
        through_evaluate(int(sys.argv[1]))
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 300)
