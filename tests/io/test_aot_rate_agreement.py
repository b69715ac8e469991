"""A foreign AOT file's frame rate is kept when its noisy timestamps agree with it.

Reference: the time axis by construction -- 3000 frames at exactly 2 kHz with 5 % Gaussian
timing noise (seed 4, whose median interval is 0.17 % off the true 0.5 ms while the mean of
the regular intervals, whose noise telescopes, is within 1e-3). The reader of files
without our own header (``MI_JSON`` removed: a foreign file) used the median alone and set
the true rate aside as metadata 'framerate' (review9, after audit 10-time's one rule
``rate_agrees``).
"""

import numpy as np
import pytest

from modalinfo.io import load
from modalinfo.io.aot import write_aot
from modalinfo.telemetry import ModalLog

pytest.importorskip("aotpy")
fits = pytest.importorskip("astropy.io.fits")


def _foreign(tmp_path):
    rng = np.random.default_rng(4)
    t = np.arange(3000) / 2000.0 + rng.normal(0.0, 0.05 / 2000.0, 3000)
    assert abs(np.median(np.diff(t)) * 2000.0 - 1.0) > 1e-3  # the median alone disagrees
    path = write_aot(ModalLog(rng.standard_normal((3000, 3)), timestamps=t, rate=2000.0),
                     tmp_path / "a.fits")
    with fits.open(path, mode="update") as hdus:
        found = [h for h in hdus if "MI_JSON" in h.header]
        assert found
        for h in found:
            del h.header["MI_JSON"]
    return path, t


def test_true_rate_of_noisy_timestamps_is_kept(tmp_path):
    path, t = _foreign(tmp_path)
    back = load(path)
    assert back.rate == 2000.0 and "framerate" not in back.metadata
    np.testing.assert_array_equal(back.timestamps, t)
