"""The quality pass's per-mode fits against per-mode references (issue 27, left28-quality).

The quality pass solves its small least-squares problems (the AR(4) predictor of each
mode, the AR(4) fit with a constant and a step of the level rule) and takes its medians
for every mode at once. References, computed here column by column from the data alone
(not from the code's intermediates): ``numpy.linalg.lstsq`` on each mode's own lag
matrix (the fits), ``numpy.median`` (centres, MADs, block scales),
``scipy.fft.dct`` and ``scipy.stats.f`` (the level rule's EWC F test, Mueller 2007),
on a seeded log with a glitched frame, a one-mode outlier, a stuck run, a level step
and a change of spread planted at known frames (flags compared exactly with the planted
frames; statistics within 1e-10 relative).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import fft, stats

from modalinfo._stats import (
    MEMORY_FLATNESS,
    MEMORY_GRID,
    MEMORY_MARGIN_SE,
    MEMORY_MAX_TERMS,
    fractional_cosine_variances,
)
from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.quality import MAD_TO_SIGMA

T, M, P = 3000, 10, 4
GLITCH, SPIKE, STUCK, STEP = 700, 1500, (2000, 2020), 1500


def _log() -> np.ndarray:
    rng = np.random.default_rng(28)
    e = rng.standard_normal((T, M))
    x = np.empty((T, M))
    x[0] = e[0]
    for t in range(1, T):
        x[t] = 0.9 * x[t - 1] + e[t]
    x[GLITCH] += 40.0  # a glitched frame: every mode
    x[SPIKE, 2] -= 40.0  # one mode's outlier
    x[STUCK[0]:STUCK[1], 4] = x[STUCK[0], 4]  # a stuck run of 20
    x[STEP:, 6] += 4.0  # a level step (marginal sd 2.3)
    x[T // 2:, 8] *= 3.0  # a change of spread (seeing)
    return x


def _lstsq_ar(y: np.ndarray, x: np.ndarray, lim: float) -> np.ndarray:
    """One mode's AR fit: rows with a gross predictor out, then refits without big residuals."""
    keep = (np.abs(x) <= lim).all(axis=1)
    y, x = y[keep], x[keep]
    c = np.linalg.lstsq(x, y, rcond=None)[0]
    for _ in range(2):
        e = y - x @ c
        s = MAD_TO_SIGMA * np.median(np.abs(e - np.median(e)))
        good = np.abs(e - np.median(e)) <= 5.0 * s
        if s == 0 or good.sum() <= 2 * P or good.all():
            break
        c = np.linalg.lstsq(x[good], y[good], rcond=None)[0]
    return c


def _lstsq_level(x: np.ndarray, memory: bool = True) -> tuple[float, int, int, float]:
    """EWC F test of the first cosine term; B from an AR(4) + constant + step lstsq fit.

    With ``memory`` (the level rule since fix54-a): each denominator term also divided
    by its share of the fractional law at ``d``, the local Whittle estimate (grid, plus
    ``MEMORY_MARGIN_SE`` s.e.) from the AR-whitened cosine terms ``j >= 2`` of the
    series less its lstsq step and linear trend, over the band where the AR spectrum
    stays within ``MEMORY_FLATNESS`` of its first value (the shares, exact for fGn, are
    checked in tests/telemetry/test_level_long_memory_fix54a.py).
    """
    n = x.size
    xc = (x - x.mean()) / np.max(np.abs(x - x.mean()))
    frame = int(np.argmax(np.abs(np.cumsum(xc)[:-1]))) + 1
    shift = float(x[frame:].mean() - x[:frame].mean())
    t = np.arange(P, n)
    lags = np.column_stack([xc[P - i:n - i] for i in range(1, P + 1)]
                           + [np.ones(n - P), (t >= frame).astype(float)])
    a = np.linalg.lstsq(lags, xc[P:], rcond=None)[0][:P]
    wide = min(MEMORY_MAX_TERMS, (n - 1) // 2) + 1
    j = np.arange(1, wide + 1)
    f = 1.0 / np.abs(1.0 - np.exp(-1j * np.pi * np.outer(j, np.arange(1, P + 1)) / n) @ a) ** 2
    flat = f[:41] / f[0] >= 0.9
    terms = min(40 if flat.all() else int(np.argmin(flat)) - 1, (n - 1) // 2)
    if terms < 6:
        return math.nan, terms, frame, shift
    c = fft.dct(xc, type=2, norm="ortho")[1:wide + 1]
    white = f[0] / f
    shape = np.ones(terms + 1)
    if memory:
        near = f / f[0] >= MEMORY_FLATNESS
        band = max(terms, wide - 1 if near.all() else int(np.argmin(near)) - 1)
        tt = np.arange(n)
        design = np.column_stack([np.ones(n), (tt >= frame).astype(float), tt])
        rest = xc - design @ np.linalg.lstsq(design, xc, rcond=None)[0]
        w = (fft.dct(rest, type=2, norm="ortho")[2:band + 2] ** 2) * white[1:band + 1]
        table = fractional_cosine_variances()[:, 2:band + 2]
        objective = np.log(np.mean(w / table, axis=1)) + np.mean(np.log(table), axis=1)
        step = MEMORY_MARGIN_SE * 0.5 / math.sqrt(band) / 0.01
        row = min(len(MEMORY_GRID) - 1, int(round(int(np.argmin(objective)) + step)))
        shape = fractional_cosine_variances()[row, 1:terms + 2]
    denom = np.mean(c[1:terms + 1] ** 2 * white[1:terms + 1] / shape[1:])
    return float(stats.f.sf(c[0] ** 2 / denom, 1, terms)), terms, frame, shift


def _lag1(a: np.ndarray) -> float:
    d = a / np.max(np.abs(a))
    d = d - d.mean()
    return float(d[1:] @ d[:-1]) / float(d @ d)


def _mad(a: np.ndarray) -> np.ndarray:
    return np.median(np.abs(a - np.median(a, axis=0)), axis=0)


def _close(a, b) -> None:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-10 * float(np.max(np.abs(b))))


def test_report_matches_per_mode_lstsq_references():
    x = _log()
    r = assess_quality(x)
    med = np.median(x, axis=0)
    sigma = MAD_TO_SIGMA * _mad(x)
    _close(r.median, med)
    _close(r.sigma, sigma)
    # the AR(4) predictor of each mode, by lstsq on its own lag matrix
    y = x[P:] - med
    lag = np.stack([x[P - i:T - i] - med for i in range(1, P + 1)], axis=1)
    coef = np.column_stack([_lstsq_ar(y[:, j], lag[:, :, j], 5.0 * sigma[j])
                            for j in range(M)])
    centre, thr, got_coef, cen_e, thr_e, _ = r.predictor
    _close(got_coef, coef)
    e = y - np.einsum("tim,im->tm", lag, coef)
    _close(cen_e, np.median(e, axis=0))
    _close(thr_e, r.k * MAD_TO_SIGMA * _mad(e))
    _close(thr, r.k * sigma)
    blocks = np.array([_mad(b) for b in np.array_split(e, 8, axis=0)])
    _close(r.scale_ratio, np.median(blocks.max(axis=0) / blocks.min(axis=0)))
    # effective frames: the robust lag-1 of the innovations (MADs of sums and differences)
    s_p, s_m = _mad(e[:-1] + e[1:]) ** 2, _mad(e[:-1] - e[1:]) ** 2
    rho = float(np.clip(np.median((s_p - s_m) / (s_p + s_m)), 0.0, 0.999))
    _close(r.effective_frames, (T - P) * (1 - rho) / (1 + rho))
    # the level rule, column by column, Bonferroni at 1 %
    level = [(j, _lstsq_level(x[:, j])) for j in range(M)]
    judged = [(j, t) for j, t in level if math.isfinite(t[0])]
    want = [(f"col{j}", t[2], t[3], t[0]) for j, t in judged if t[0] < 0.01 / len(judged)]
    assert r.level_judged == len(judged)
    assert [(lab, fr) for lab, fr, _, _ in r.level_steps] == [(lab, fr) for lab, fr, _, _ in want]
    assert [lab for lab, *_ in want] == ["col6"]
    _close([s for _, _, s, _ in r.level_steps], [s for _, _, s, _ in want])
    _close([p for *_, p in r.level_steps], [p for *_, p in want])
    # the spread rule: the level rule on absolute deviations, at 0.25 %, step modes skipped
    dev = np.abs(x - med)
    cols = [j for j in range(M) if j != 6 and T * (1 - (r1 := min(max(_lag1(dev[:, j]), 0.0),
                                                                   0.999))) / (1 + r1) >= 100]
    vlevel = [(j, _lstsq_level(dev[:, j], memory=False)) for j in cols]
    vjudged = [(j, t) for j, t in vlevel if math.isfinite(t[0])]
    vwant = [(f"col{j}", t[2], t[0]) for j, t in vjudged if t[0] < 0.0025 / len(vjudged)]
    assert r.variance_judged == len(vjudged)
    assert [(lab, fr) for lab, fr, _, _ in r.variance_steps] == [(lab, fr) for lab, fr, _ in
                                                                   vwant]
    assert "col8" in [lab for lab, *_ in vwant]
    _close([p for *_, p in r.variance_steps], [p for *_, p in vwant])
    assert r.stationary is False
    # flags: exactly the planted frames
    assert r.glitch_frames.tolist() == [GLITCH]
    assert r.outlier_frames.tolist() == [GLITCH, SPIKE]
    assert r.outliers.tolist() == [1, 1, 2] + [1] * (M - 3)
    assert r.stuck_frames.tolist() == list(range(*STUCK))
    assert r.stuck.tolist() == [0, 0, 0, 0, STUCK[1] - STUCK[0]] + [0] * (M - 5)
    assert r.flagged_frames.tolist() == sorted({GLITCH, SPIKE, *range(*STUCK)})
