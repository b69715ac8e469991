"""Fixes 40-a (round 39 PART a, T02, T06): a >= 1 kHz loop's frame times in ms are warned.

Frame times of a 1 kHz (2 kHz) loop written in ms read as a 1 Hz (2 Hz) log inside the
1 Hz floor of ``WFS_RATE_RANGE`` without a word, and every lag, horizon and the forecast
table's "1 frame = 1000 ms" followed. Frame times now give a rate below
``TIMES_RATE_FLOOR`` = 10 Hz a warning naming the rate, the rate if the times were in ms
and in us, and how to give the rate; the wavefront sensors of AO loops run at ~100 Hz -
10 kHz (Hardy 1998; Roddier 1999; solar AO 1-2 kHz, Rimmele & Marino 2011). A rate
given as ``rate`` keeps the 1 Hz floor (slow guiders, seeing monitors). Reference: the
rate of the times by hand, 1 / (median interval).
"""

import warnings

import numpy as np
import pytest

from modalinfo.common.validation import CLI_TIMES_ADVICE
from modalinfo.telemetry import ModalLog

from ._cli_stderr import cli_stderr


def _coeffs(n=200):
    return np.random.default_rng(0).standard_normal((n, 3))


@pytest.mark.parametrize("loop_hz", [1000.0, 2000.0, 4000.0])
def test_ms_times_of_a_fast_loop_warned_naming_the_rates(loop_hz):
    t_ms = np.arange(200) * (1000.0 / loop_hz)  # ms, read as s
    with pytest.warns(UserWarning) as rec:
        log = ModalLog(_coeffs(), timestamps=t_ms)
    texts = [str(w.message) for w in rec]
    assert len(texts) == 1, texts
    read = loop_hz / 1000.0  # 1 / median interval
    assert log.rate == pytest.approx(read)  # kept: analysed as given
    assert f"frame rate of {read:.3g} Hz" in texts[0] and "below 10 Hz" in texts[0]
    assert f"timestamps / 1000 is {loop_hz:.3g} Hz" in texts[0]
    assert f"in us {loop_hz * 1000:.3g} Hz" in texts[0]
    assert "or the rate in Hz instead of the times" in texts[0]


@pytest.mark.parametrize("build", [
    lambda: ModalLog(_coeffs(), rate=1.0),  # a slow log given its rate
    lambda: ModalLog(_coeffs(), rate=0.2),  # inside WFS_RATE_RANGE? no: below 1 Hz
    lambda: ModalLog(_coeffs(), timestamps=np.arange(200) * 0.1),  # 10 Hz, the edge
    lambda: ModalLog(_coeffs(), timestamps=np.arange(200) * 0.01),  # 100 Hz
])
def test_given_rates_and_ao_times_keep_their_rules(build):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        build()
    texts = [str(w.message) for w in rec]
    if texts:  # only rate=0.2, by the 1 Hz floor of a given rate, as before
        assert len(texts) == 1 and "`rate` = 0.2 Hz is below 1 Hz" in texts[0]


def test_command_line_ms_time_column_warned_once_with_the_times_advice(tmp_path, capsys):
    t = np.arange(400) * 1.0  # 1 kHz written in ms
    x = _coeffs(400)
    rows = "".join(f"{tk!r},{a!r},{b!r},{c!r}\n" for tk, (a, b, c) in zip(t.tolist(), x.tolist(),
                                                                          strict=True))
    path = tmp_path / "ms.csv"
    path.write_text("time,Z2,Z3,Z4\n" + rows)
    code, lines = cli_stderr(["info", path], capsys)
    assert code == 0 and len(lines) == 1, lines
    assert "frame rate of 1 Hz" in lines[0] and "timestamps / 1000 is 1e+03 Hz" in lines[0]
    assert lines[0].endswith(f"({CLI_TIMES_ADVICE}).")
