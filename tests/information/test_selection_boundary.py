"""The input-selection stopping rule at its boundary: p-values at alpha, and the budget.

References (the documented rule, modalinfo/information/selection.py, checked from outside):
- the permutation p-value ``(1 + #{null >= observed}) / (1 + N)`` (Davison & Hinkley
  1997, eq. 4.11; Phipson & Smyth 2010): an input far stronger than every surrogate has
  p = 1 / (N + 1) exactly, so with N = 19 surrogates and alpha = 0.05 it is selected (a
  step rejects when p <= alpha), with alpha just below 0.05 it is not, and with N = 18
  (p = 1/19 > 0.05) no input can ever be selected;
- the fixed-sequence procedure (each step tested only after every earlier one
  rejected): with the same seed the surrogates' shifts, hence the sequence of p-values,
  do not depend on alpha, so the number of inputs at level alpha is the index of the
  first p-value above alpha in the sequence a lenient search reports; checked at
  alpha = each p-value (kept) and just below it (stops there);
- ties count against the candidate (``>=``): periodic series whose surrogate shifts are
  whole periods make every surrogate the original array, hence p = 1 exactly;
- the budget: ``max_inputs`` = k gives exactly k inputs when more are significant, the
  first k of the unlimited search, and says so.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import select_inputs


@pytest.fixture(scope="module")
def coupled():
    """Target s0 driven by s1[t], s2[t-1], s3[t] one step ahead, plus a weak noise."""
    rng = np.random.default_rng(11)
    n = 500
    s = rng.standard_normal((n, 4))
    y = np.zeros(n)
    y[2:] = (0.9 * s[1:-1, 1] + 0.6 * s[:-2, 2] + 0.35 * s[1:-1, 3]
             + 0.3 * rng.standard_normal(n - 2))
    s[:, 0] = y
    return s


def _select(data, **kw):
    kw.setdefault("intervals", False)
    return select_inputs(data, 0, horizon=1, max_lag=3, seed=4, **kw)


def test_strongest_input_has_the_smallest_p_value_and_alpha_is_inclusive(coupled):
    at = _select(coupled, alpha=0.05, n_surrogates=19, max_inputs=1)
    assert len(at.inputs) == 1
    # 1 / (N + 1) with no surrogate reaching the observed gain; 1.0 / 20.0 is the
    # correctly rounded 0.05, the same double as the literal
    assert at.inputs[0].pvalue == 1.0 / 20.0 == 0.05
    assert at.inputs[0].label == "m1[t]"
    # just below 1/20, and N = 18 (smallest p-value 1/19 > 0.05): no step could ever
    # pass, so the search is refused rather than reported as "nothing significant"
    with pytest.raises(ValueError, match=r"`n_surrogates`=19 cannot reach `alpha`"):
        _select(coupled, alpha=float(np.nextafter(0.05, 0.0)), n_surrogates=19)
    with pytest.raises(ValueError, match=r"smallest p-value of 18 surrogates is 1/19"):
        _select(coupled, alpha=0.05, n_surrogates=18)


def test_fixed_sequence_stops_at_the_first_p_value_above_alpha(coupled):
    lenient = _select(coupled, alpha=0.999, n_surrogates=39, max_inputs=8)
    seq = [s.pvalue for s in lenient.inputs]
    if np.isfinite(lenient.last_pvalue):
        seq.append(lenient.last_pvalue)
    seq = np.array(seq)
    # every p-value is a multiple of 1 / (N + 1) between 1 / (N + 1) and 1
    k = seq * 40.0
    np.testing.assert_allclose(k, np.round(k), atol=1e-9)
    assert np.all((seq >= 1.0 / 40.0) & (seq <= 1.0))
    # the three true inputs first, at the smallest p-value; then noise, p-values that vary
    assert {s.label for s in lenient.inputs[:3]} == {"m1[t]", "m2[t-1]", "m3[t]"}
    assert np.all(seq[:3] == 1.0 / 40.0)
    assert np.unique(seq).size >= 3, "the sequence needs p-values on both sides of alpha"
    for alpha in sorted(set(seq.tolist())):
        for a in (alpha, float(np.nextafter(alpha, 0.0))):
            if a >= 1.0:
                continue
            if a < 1.0 / 40.0:  # below the smallest p-value: no step could pass, refused
                with pytest.raises(ValueError, match="cannot reach"):
                    _select(coupled, alpha=a, n_surrogates=39, max_inputs=8)
                continue
            expected = int(np.argmax(seq > a)) if np.any(seq > a) else seq.size
            got = _select(coupled, alpha=a, n_surrogates=39, max_inputs=8)
            assert len(got.inputs) == min(expected, len(lenient.inputs)), (a, seq)
            assert [s.label for s in got.inputs] == [
                s.label for s in lenient.inputs[:len(got.inputs)]]


@pytest.mark.parametrize("budget", [1, 2, 3])
def test_max_inputs_is_a_hard_budget(coupled, budget):
    free = _select(coupled, alpha=0.05, n_surrogates=19, max_inputs=10)
    assert len(free.inputs) >= 3
    capped = _select(coupled, alpha=0.05, n_surrogates=19, max_inputs=budget)
    assert len(capped.inputs) == budget
    assert [s.label for s in capped.inputs] == [s.label for s in free.inputs[:budget]]
    assert capped.stop_reason == "budget reached"


def test_a_surrogate_equal_to_the_original_counts_against_it():
    # every series periodic with period 8 over n = 400 rows, and the surrogates' shifts
    # multiples of 8 (min_shift): each rotated candidate is the original array, so the
    # histogram estimator gives every surrogate exactly the observed gain. The
    # p-value counts ties (null >= observed): (1 + N) / (1 + N) = 1, never significant,
    # however strong the dependence (y is a function of x's last value)
    rng = np.random.default_rng(2)
    period, n_rows = 8, 400
    x = np.tile(rng.standard_normal(period), n_rows // period + 1)[:n_rows + 1]
    y = np.roll(x, 1) ** 2 + np.roll(x, 1)
    data = np.column_stack([y, x])
    sel = select_inputs(data, 0, horizon=1, max_lag=1, method="histogram",
                        n_surrogates=19, min_shift=period, alpha=0.5, intervals=False,
                        seed=1)
    assert sel.n_samples == n_rows and sel.min_shift == period
    assert sel.inputs == ()
    assert sel.last_pvalue == 1.0
