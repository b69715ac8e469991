"""Round 8 of issue 27's adversarial inputs (closedloop API): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 8, issue 27".

Reference: the documented contract of ``SimulationResult`` (bad arguments raise a
ValueError or TypeError naming them; ``nperseg`` of ``strehl_peak_spectrum`` is a
Welch segment length, a positive int, as scipy.signal.welch requires).
"""

from __future__ import annotations

import numpy as np
import pytest

from closedloop import simulate

from .conftest import small
from .test_result_views import _result


@pytest.fixture(scope="module")
def result():
    config = small("kaos")
    return simulate(config, 6 * config.loop.time_step, progress=False)


@pytest.mark.parametrize("refine", [0, -1])
def test_corrected_fov_refine_below_one_is_refused(result, refine):
    # c25: refine=0 stopped with an IndexError inside the interpolation
    with pytest.raises(ValueError, match=r"`refine` must be an int >= 1"):
        result.corrected_fov_diameter(0.3, refine=refine)


@pytest.mark.parametrize("nperseg", [0, -5])
def test_spectrum_segment_below_one_is_refused(result, nperseg):
    # c26: nperseg=0 was read as the default 256; -5 stopped in scipy's words
    with pytest.raises(ValueError, match=r"`nperseg` must be an int >= 1"):
        result.strehl_peak_spectrum(nperseg=nperseg)


def test_spectrum_with_a_valid_segment_still_runs(result):
    # from frame 0 (6 frames): Welch segments of 4 samples give 4 // 2 + 1 = 3 frequencies
    freqs, psd = result.strehl_peak_spectrum(nperseg=4, start=0)
    assert freqs.shape == psd.shape == (3,)


def test_a_swinging_sr_that_did_not_close_says_its_band():
    # e87: a loop at gain 0.999 whose SR peak swings between ~0 and 0.4 (mean 0.18) was
    # said to have "never rose clearly above" 2.7e-14 without the band that means it.
    # Here half the frames are at 0.4: since left24-status (K21, K22) it says that the SR
    # rose (to a median of 0.2005) and swings too widely, not "never rose"
    sr = np.where(np.arange(40) % 2 == 0, 1e-3, 0.4)
    sr[0] = 1e-3  # the open loop
    r = _result(-np.log(sr))
    status = r.loop_status
    assert status.startswith("did not close: the SR peak rose from its open-loop value "
                             "(0.001) to a median of 0.201 over the second half (mean 0.2)")
    assert "never rose" not in status and "swings too widely" in status
    tail = sr[20:]  # the band by its definition: median - 3 x 1.4826 MAD of the second half
    low = np.median(tail) - 3.0 * 1.4826 * np.median(np.abs(tail - np.median(tail)))
    assert f"reaches down to {low:.3g}" in status
