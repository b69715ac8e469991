"""The quality pass names a mode constant over the whole log (round 53 PART a, W09).

Reference: numpy (``np.ptp(column) == 0`` finds the constant columns). The module
docstring of ``modalinfo.telemetry.quality`` says such a mode "is reported as
constant, not as stuck"; before round 53 ``describe()`` of a 500-mode Kolmogorov log
with Z101 zeroed read "0 of 4000 frames flagged by ...", naming it nowhere.
"""

import numpy as np

from modalinfo.telemetry import ModalLog, assess_quality


def _log(seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.standard_normal((3000, 40)) / np.sqrt(np.arange(1, 41))


def test_constant_modes_are_named_in_describe():
    x = _log()
    x[:, 9] = 0.0
    x[:, 30] = 0.25
    modes = list(range(2, 42))
    dead = [f"Z{modes[i]}" for i in np.flatnonzero(np.ptp(x, axis=0) == 0)]
    text = assess_quality(ModalLog(x, rate=1000.0, modes=modes)).describe()
    assert "2 mode(s) constant over the whole log" in text
    assert text.endswith(": " + ", ".join(dead))


def test_constant_mode_named_beside_flagged_frames():
    x = _log()
    x[:, 4] = 0.0
    x[1000, 7] += 50.0
    text = assess_quality(ModalLog(x, rate=1000.0, modes=list(range(2, 42)))).describe()
    assert text.startswith("1 of 3000 frames flagged")
    assert "1 mode(s) constant over the whole log, not tested" in text and "Z6" in text


def test_no_constant_mode_no_note():
    text = assess_quality(ModalLog(_log(), rate=1000.0, modes=list(range(2, 42)))).describe()
    assert "constant" not in text
