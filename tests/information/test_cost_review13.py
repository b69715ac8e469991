"""``order_modes``' time check: its sample count and replicates, and the documented constants.

Review13 (planted bugs R13-C2, C4, C5). References, outside the code under test: the
samples an ordering estimates on, counted here from the log (one frame: the basis'
pixels; all frames: frames x pixels; at most ``sample_budget``); the replicates the
caller asks for; the public cost model ``least_ordering_seconds`` of those numbers (the
one estimate the command line refuses by: the library must check the same); and the
constants as measured and documented (module notes of ``modalinfo.ordering.cost``,
benchmarks/RESULTS.md "Orderings' cost ... leftovers 13": screens 0.25 ms + 1.5 ns per
sample of each score, gathering 1.5 ns per mode and sample). No timing is asserted.
"""

import numpy as np
import pytest

from modalinfo.information import MutualInformation
from modalinfo.ordering import cost, order_modes
from modalinfo.ordering import orderings as orderings_module
from modalinfo.ordering.cost import least_ordering_seconds


class _StopError(Exception):
    pass


def _no_work(monkeypatch):
    def stop(*args, **kw):
        raise _StopError("the work started")

    monkeypatch.setattr(orderings_module, "_contributions", stop)
    monkeypatch.setattr(MutualInformation, "fit", stop)


def _log(n_frames=40, n_modes=6, pixels=300):
    rng = np.random.default_rng(0)
    return (rng.standard_normal((n_frames, n_modes)) / np.arange(1, n_modes + 1),
            rng.standard_normal((pixels, n_modes)))


def test_the_replicates_count_in_the_libraries_check(monkeypatch):
    coeffs, basis = _log()
    n = min(2000, 40 * 300)
    bare, _ = least_ordering_seconds("histogram", n, 6, 0)
    full, _ = least_ordering_seconds("histogram", n, 6, 40)
    limit = 0.5 * (bare + full)
    _no_work(monkeypatch)
    with pytest.raises(ValueError, match=r"40 bootstrap replicates .*more than `max_seconds`"):
        order_modes(coeffs, basis, "mi_marginal", sample_budget=2000, n_resamples=40,
                    max_seconds=limit, seed=0)
    with pytest.raises(_StopError):  # no replicates: under the limit, the work starts
        order_modes(coeffs, basis, "mi_marginal", sample_budget=2000, n_resamples=0,
                    max_seconds=limit, seed=0)


def test_one_frame_is_estimated_on_its_pixels_not_the_budget(monkeypatch):
    coeffs, basis = _log()
    on_pixels, _ = least_ordering_seconds("histogram", 300, 6, 0)  # one frame: 300 pairs
    on_budget, _ = least_ordering_seconds("histogram", 2000, 6, 0)
    assert on_pixels < on_budget
    _no_work(monkeypatch)
    with pytest.raises(_StopError):  # under the limit: the work starts
        order_modes(coeffs, basis, "mi_marginal", sample_budget=2000, frame=3,
                    n_resamples=0, max_seconds=0.5 * (on_pixels + on_budget), seed=0)


def test_the_screen_and_gathering_constants_are_the_documented_ones(monkeypatch):
    # the estimator's own terms set to 0: what is left is the screens and the gathering
    monkeypatch.setitem(cost.MI_SECONDS_PER_CALL, "histogram", 0.0)
    monkeypatch.setitem(cost.MI_SECONDS_PER_SAMPLE, "histogram", lambda n: 0.0)
    n, m, r = 25_824, 150, 40
    seconds, calls = least_ordering_seconds("histogram", n, m, r)
    assert calls == (3 * m - 2) + r * (2 * m - 2)
    expected = calls * (0.25e-3 + 1.5e-9 * n) + (1 + r) * m * n * 1.5e-9
    assert seconds == pytest.approx(expected, rel=1e-12)
