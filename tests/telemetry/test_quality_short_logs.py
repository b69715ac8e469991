"""A log too short (in effective frames) to assess outliers says so; it is never "clean".

References (outside the code under test): the effective sample size of the innovations
of a fitted AR(p), ``(N - p) (1 - r) / (1 + r)`` (Bartlett 1946, one frame per fitted
coefficient), written out here for white innovations (r = 0: 15 frames and p = 4 give
11, under the edge of 12); a planted 100-sigma value at a known frame; the one-line
refusal contract of ``--outliers raise``; the quality line of ``info``. The issue's case
(rho = 0.99, 50 frames: 0.25 independent frames of levels) was "too short" while the
levels were tested; its innovations are white, so it is now assessed and the glitch
found (issue 27, leftovers 11).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog, apply_outlier_policy, assess_quality
from modalinfo.telemetry.quality import MIN_EFFECTIVE_FRAMES

T, M, FRAME = 50, 27, 25
SHORT = 15  # (15 - 4) x 1 = 11 effective frames of white innovations: below 12


def _ar1(rho: float, seed: int, T: int = T) -> np.ndarray:
    """T frames of a stationary unit-variance AR(1) per mode, + 100 sigma at one value."""
    e = np.random.default_rng(seed).standard_normal((2000 + T, M))
    x = lfilter([np.sqrt(1.0 - rho**2)], [1.0, -rho], e, axis=0)[-T:]  # burnt in
    x[FRAME if T > FRAME else T // 2, 0] += 100.0  # frame 7 of SHORT
    return x


def test_a_100_sigma_glitch_in_15_frames_is_too_short_to_assess(tmp_path, capsys):
    # issue 27 leftovers: k was 149 on a log this short and the report said what a clean
    # log says when nothing passed it; 15 white frames less 4 coefficients are 11 < 12
    assert (SHORT - 4) < MIN_EFFECTIVE_FRAMES
    r = assess_quality(_ar1(0.99, 1, SHORT))
    assert not r.assessed and not r.clean and r.k == np.inf
    assert r.effective_frames < MIN_EFFECTIVE_FRAMES
    assert r.describe().startswith("too short to assess outliers and glitches: ")
    assert r.to_dict()["assessed"] is False and r.to_dict()["k"] is None
    log = ModalLog(_ar1(0.99, 1, SHORT), rate=1000.0)
    with pytest.raises(ValueError, match=r"^`policy`='raise': too short to assess"):
        apply_outlier_policy(log, "raise")
    out, _ = apply_outlier_policy(log, "clip")
    assert np.array_equal(out.coeffs, log.coeffs)  # nothing acted on, and recorded
    assert out.metadata["outliers"][-1]["action"] == "too short to assess; data used as is"
    path = save(log, tmp_path / "short.npz")
    assert main(["info", str(path)]) == 0
    line = [s for s in capsys.readouterr().out.splitlines() if s.startswith("quality")]
    assert line and "too short to assess" in line[0] and "0 of 15 frames" not in line[0]
    # a threshold given by the caller is applied as asked (the choice is theirs)
    assert assess_quality(_ar1(0.99, 1, SHORT), k=20.0).outlier_frames.tolist() == [7]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_glitch_in_50_frames_of_rho_099_is_assessed_on_the_innovations(seed):
    # the levels hold 50 x 0.01 / 1.99 = 0.25 independent frames, the AR(1) innovations
    # 50 - 4 white ones: assessed, and the planted value is the only one flagged
    r = assess_quality(_ar1(0.99, seed))
    assert r.assessed and r.effective_frames > MIN_EFFECTIVE_FRAMES
    assert r.outlier_frames.tolist() == [FRAME]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_the_same_glitch_in_50_white_frames_is_assessed_and_found(seed):
    # rho = 0: N = 50 independent frames, above the edge, so the default threshold holds
    r = assess_quality(_ar1(0.0, seed))
    assert r.assessed and r.effective_frames > MIN_EFFECTIVE_FRAMES
    assert r.outlier_frames.tolist() == [FRAME] and r.k < 10
