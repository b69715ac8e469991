"""One copy of the AR fits: the scale shift and the level rule share ``stacked_ar_fits``.

Issue 27, left28-misc. References, outside the code: one ``numpy.linalg.lstsq`` per
column on the design written out here (``[x_(t-1) .. x_(t-p), 1]``, and a unit step
for the level rule), and ``_scale_shift``'s documented ratio rebuilt by hand from those
fits (test mean square of the frozen model's innovations over ``1 + (p + 1) / (n - p)``,
over ``RSS / (n - 2p - 1)``). Tolerance 1e-9 relative: the stacked normal equations
with two refinement steps are documented within 1e-11 of ``lstsq`` (``stacked_lstsq``);
the series include a random walk and an AR(1) at 0.999 (the worst conditioned AR
designs), values near 1e150 and 1e-150, and more modes than one block of
``_scale_shift`` holds. The ratio test passes on the per-mode code before the change
too (the numbers did not move); the stacked helper is new.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

from modalinfo._stats import INNOVATION_ORDER, stacked_ar_fits

ev = importlib.import_module("modalinfo.forecast.evaluate")  # the module, not the function

P = INNOVATION_ORDER


def _ar1(n: int, m: int, phi: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = rng.standard_normal((n, m))
    for t in range(1, n):
        x[t] += phi * x[t - 1]
    return x


def _design(col: np.ndarray, step: int | None = None) -> np.ndarray:
    n = col.size
    parts = [col[P - i:n - i] for i in range(1, P + 1)] + [np.ones(n - P)]
    if step is not None:
        parts.append((np.arange(P, n) >= step).astype(float))
    return np.column_stack(parts)


def _series() -> np.ndarray:
    rng = np.random.default_rng(4)
    return np.column_stack([_ar1(3000, 2, 0.9, 1), _ar1(3000, 1, 0.999, 2),
                            np.cumsum(rng.standard_normal(3000)),
                            np.sin(0.05 * np.arange(3000)) + 0.1 * rng.standard_normal(3000)])


@pytest.mark.parametrize("with_step", [False, True])
def test_stacked_ar_fits_match_one_lstsq_per_column(with_step):
    x = _series()
    step = np.array([700, 1500, 2200, 10, 2990]) if with_step else None
    coef, e = stacked_ar_fits(x, P, step=step, residuals=True)
    for j in range(x.shape[1]):
        a = _design(x[:, j], None if step is None else int(step[j]))
        ref = np.linalg.lstsq(a, x[P:, j], rcond=None)[0]
        np.testing.assert_allclose(coef[j], ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())
        res = x[P:, j] - a @ ref
        np.testing.assert_allclose(e[:, j], res, atol=1e-9 * np.abs(x[:, j]).max())


def _ratio_by_hand(x: np.ndarray, n_train: int) -> np.ndarray:
    """``_scale_shift``'s documented ratio, one lstsq per mode (NaN where not judged)."""
    out = np.full(x.shape[1], np.nan)
    for m in range(x.shape[1]):
        col = x[:n_train, m]
        s = col.std()
        if not s > 0:
            continue
        a = _design(col / s)
        c = np.linalg.lstsq(a, col[P:] / s, rcond=None)[0]
        rss = float(np.sum((col[P:] / s - a @ c) ** 2)) * s * s
        full = x[n_train - P:, m]
        pred = _design(full) @ np.r_[c[:P], c[P] * s]
        ms_test = np.mean((full[P:] - pred) ** 2)
        n_rows = n_train - P
        out[m] = ms_test / (1 + (P + 1) / n_rows) / (rss / (n_rows - P - 1))
    return out


@pytest.mark.parametrize("scale", [1.0, 1e150, 1e-150])
def test_scale_shift_ratios_match_per_mode_lstsq(scale, monkeypatch):
    monkeypatch.setattr(ev, "_SHIFT_BLOCK_VALUES", 3000, raising=False)  # 2 modes a block
    x = _ar1(3000, 5, 0.9, 7)
    x[1500:, 2] *= 2.0  # one mode shifts in scale
    x *= scale
    ratio, _, shifted = ev._scale_shift(x, x[:1500], 1500, 400, 0.01)
    np.testing.assert_allclose(ratio, _ratio_by_hand(x, 1500), rtol=1e-9)
    assert shifted.tolist() == [False, False, True, False, False]
