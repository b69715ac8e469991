"""Least-squares selections and transfer maps on glitched logs warn (round 53 PART a).

References: the exact model (AR(1) a = 0.9 modes whose innovations share a Kolmogorov
Noll covariance: given a mode's own past no other series adds information, so the exact
input set is the target's lag 1 and every transfer entropy is 0), and numpy least
squares for the AR(4) innovations of the outlier rule (each column fitted by
``numpy.linalg.lstsq`` on its 4 previous values and a constant, robust sigmas from the
1.4826 MAD). Round 53 PART a: 4 frames glitched by +-20 sd in 3 of 40 modes gave false
inputs in 20 of 20 ``select_inputs`` calls (0 of 20 clean) and false cells in 10 of 10
``transfer_entropy_map`` calls (1 of 10 clean), without a word. The rule's stated
false-alarm rate on Gaussian logs is 1e-4 per call (``HEAVY_TAIL_ALPHA``), so the clean
cases below fail by chance with probability ~1e-3 in all.
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import select_inputs, transfer_entropy_map
from modalinfo.information.resampling import OutlierWarning, outlier_columns
from modalinfo.telemetry import ModalLog, apply_outlier_policy

from ._glitched_ar1 import glitched as _glitched
from ._glitched_ar1 import noll_ar1 as _ar1


def _outlier_warnings(fn) -> list[str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fn()
    return [str(w.message) for w in caught if issubclass(w.category, OutlierWarning)]


def test_outlier_columns_against_numpy_lstsq():
    y, frames, cols = _glitched(_ar1(3000, 6, 1), 1)
    got = {c: (t, z) for c, t, z, _ in outlier_columns(y)}
    assert set(got) == set(cols.tolist())
    for c in cols:
        x = y[:, c] - y[:, c].mean()
        x = x / np.abs(x).max()
        design = np.column_stack([x[4 - i - 1: len(x) - i - 1] for i in range(4)]
                                 + [np.ones(len(x) - 4)])
        coef = np.linalg.lstsq(design, x[4:], rcond=None)[0]
        e = x[4:] - design @ coef
        dev = np.abs(e - np.median(e))
        z = dev.max() / (1.4826 * np.median(dev))
        assert got[c][1] == pytest.approx(z, rel=1e-3)
        assert got[c][0] == int(np.argmax(dev)) + 4
        assert got[c][0] in set(frames.tolist()) | set((frames + 1).tolist())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_select_inputs_names_glitched_series(seed):
    clean = _ar1(4000, 40, 54000 + seed)
    glitched, _, cols = _glitched(clean, seed)
    run = lambda y: lambda: select_inputs(y, 0, max_lag=2, n_surrogates=19,  # noqa: E731
                                          intervals=False, seed=seed)
    msgs = _outlier_warnings(run(glitched))
    assert len(msgs) == 1 and msgs[0].startswith("select_inputs: 3 series hold outliers")
    assert all(f"m{c} (" in msgs[0] for c in cols)
    assert _outlier_warnings(run(clean)) == []


@pytest.mark.parametrize("seed", [0, 1])
def test_transfer_map_names_glitched_series(seed):
    clean = _ar1(4000, 20, 55000 + seed)
    glitched, _, cols = _glitched(clean, seed)
    run = lambda y: lambda: transfer_entropy_map(y, lags=2, n_surrogates=19,  # noqa: E731
                                                 seed=seed)
    msgs = _outlier_warnings(run(glitched))
    assert len(msgs) == 1 and msgs[0].startswith("transfer_entropy_map: 3 series")
    assert all(f"m{c} (" in msgs[0] for c in cols)
    assert _outlier_warnings(run(clean)) == []


def test_clipped_log_selects_the_exact_input_without_a_warning():
    glitched, _, _ = _glitched(_ar1(4000, 40, 54000), 0)
    log, _ = apply_outlier_policy(ModalLog(glitched, rate=1000.0), "clip")
    coeffs = np.asarray(log.coeffs)
    with warnings.catch_warnings():
        warnings.simplefilter("error", OutlierWarning)
        sel = select_inputs(coeffs, 0, max_lag=2, n_surrogates=19, intervals=False, seed=0)
    assert [s.label for s in sel.inputs] == ["m0[t]"]
