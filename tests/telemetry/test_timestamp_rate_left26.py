"""Leftovers 26-rate: a rate from frame times, the command line's advice, ``bins`` as a 0-d string.

References: the frame rates of wavefront sensors, 1 Hz - 100 kHz
(``modalinfo.common.validation.WFS_RATE_RANGE``, on which ``rate=0.001`` is warned), and
the rate of frame times by hand: times 1000 s apart are 1 / 1000 s = 0.001 Hz, times
5 us apart 2e5 Hz, a 1 kHz log with a 2000 s gap has a median interval of 1 ms (1 kHz)
and a mean rate of (n - 1) / (t[-1] - t[0]) < 1 Hz. Adversarial round 25 P13 / P15 /
P16: a caller's or a foreign file's times 1000 s apart gave 0.001 Hz silently while
``rate=0.001`` warned. A file modalinfo wrote is read as stored (Leftovers 23-plaus).
The command lines' words: ``modalinfo.common.validation.CLI_RATE_ADVICE`` and
``CLI_TIMES_ADVICE`` against the Python caller's ``PYTHON_ADVICE``. ``bins``: the string
rule ``"auto"`` gives the same MI as ``np.array("auto")`` (the one value of a 0-d array).
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest
from astropy.io import fits

from modalinfo.common.validation import (
    CLI_RATE_ADVICE,
    CLI_TIMES_ADVICE,
    PYTHON_ADVICE,
)
from modalinfo.information import mutual_information
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

from ._cli_stderr import cli_stderr

# frame times: below 10 Hz since fixes 40-a (validation.TIMES_RATE_FLOOR; 1 Hz before)
SLOW = r"`timestamps` give a frame rate of 0\.001 Hz \(median interval 1000 s\), below 10 Hz"


def _coeffs(n: int = 20) -> np.ndarray:
    return np.random.default_rng(0).standard_normal((n, 3))


def _one_warning(match: str, build, *args, **kwargs):
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        out = build(*args, **kwargs)
    texts = [str(w.message) for w in rec if issubclass(w.category, UserWarning)]
    assert len(texts) == 1, texts
    assert re.search(match, texts[0]), texts[0]
    return out, texts[0]


def _silent(build, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return build(*args, **kwargs)


# ------------------------------------------------------------- the API: ModalLog, readers
def test_modallog_times_1000_s_apart_warned_once_with_python_advice():
    log, text = _one_warning(SLOW, ModalLog, _coeffs(), timestamps=np.arange(20) * 1000.0)
    assert log.rate == pytest.approx(0.001)  # kept: an archive is analysed as given
    assert "a clock in ms read as seconds" in text and text.endswith(f"({PYTHON_ADVICE}).")


def test_modallog_times_5_us_apart_warned():
    _one_warning(r"`timestamps` give a frame rate of 2e\+05 Hz .* above 100000 Hz",
                 ModalLog, _coeffs(), timestamps=np.arange(20) * 5e-6)


# 1 kHz, the 10 Hz edge of frame times (fixes 40-a; 1 Hz before), 50 kHz
@pytest.mark.parametrize("step", [1e-3, 0.1, 2e-5])
def test_usual_times_silent(step):
    _silent(ModalLog, _coeffs(), timestamps=np.arange(20) * step)


def test_gapped_1_khz_night_silent():
    # median interval 1 ms (1 kHz); mean rate 19 / 2000.018 s < 1 Hz
    t = np.r_[np.arange(10) * 1e-3, 2000.0 + np.arange(10) * 1e-3]
    log = _silent(ModalLog, _coeffs(), timestamps=t)
    assert log.rate < 1.0


def test_rate_and_times_warned_once_by_the_rate():
    _one_warning(r"`rate` = 0\.001 Hz is below 1 Hz", ModalLog, _coeffs(), rate=0.001,
                 timestamps=np.arange(20) * 1000.0)


def test_a_refused_log_is_not_warned():
    x = _coeffs()
    x[3, 1] = np.nan
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="must be finite"):
            ModalLog(x, timestamps=np.arange(20) * 1000.0)


def test_nanosecond_clocks_unchanged():
    # float ns at 1 kHz: a 1e-6 Hz log, outside 1 mHz - 1 MHz, which the analyses and
    # the commands refuse (log_rate_problem): no warning first, as before
    log = _silent(ModalLog, _coeffs(), timestamps=np.arange(20) * 1e6)
    assert log.rate == pytest.approx(1e-6)
    with pytest.raises(ValueError, match="integers with a median step of 1000000"):
        _silent(ModalLog, _coeffs(), timestamps=np.arange(20, dtype=np.int64) * 1_000_000)


def _csv(path, t, x):
    rows = "".join(f"{tk!r},{a!r},{b!r},{c!r}\n"
                   for tk, (a, b, c) in zip(np.asarray(t, float).tolist(), x.tolist(), strict=True))
    path.write_text("time,Z2,Z3,Z4\n" + rows)
    return path


def _hdf5(path, t, x):
    import h5py

    with h5py.File(path, "w") as f:
        f.create_dataset("loop/modes", data=x)
        f.create_dataset("loop/time", data=t)
    return path


def _fits(path, t, x):
    cols = [fits.Column(name="TIME", format="D", array=t)]
    cols += [fits.Column(name=f"Z{j}", format="D", array=x[:, k]) for k, j in enumerate([2, 3, 4])]
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(cols)]).writeto(path)
    return path


@pytest.mark.parametrize("write, ext", [(_csv, "csv"), (_hdf5, "h5"), (_fits, "fits")])
def test_foreign_file_with_a_1000_s_time_column_warned(tmp_path, write, ext):
    path = write(tmp_path / f"slow.{ext}", np.arange(20) * 1000.0, _coeffs())
    log, _ = _one_warning(SLOW, load, path)
    assert log.rate == pytest.approx(0.001)


def test_foreign_gapped_1_khz_file_silent(tmp_path):
    t = np.r_[np.arange(10) * 1e-3, 2000.0 + np.arange(10) * 1e-3]
    assert _silent(load, _csv(tmp_path / "gap.csv", t, _coeffs())).rate < 1.0


@pytest.mark.parametrize("ext, fmt", [("npz", None), ("csv", None), ("h5", None),
                                      ("fits", "fits"), ("fits", "aot")])
def test_own_file_times_read_as_stored(tmp_path, ext, fmt):
    log, _ = _one_warning(SLOW, ModalLog, _coeffs(), timestamps=np.arange(20) * 1000.0)
    path = save(log, tmp_path / f"own.{ext}", fmt=fmt)
    back = _silent(load, path)
    np.testing.assert_array_equal(back.timestamps, log.timestamps)


# ------------------------------------------------------------------ the command line
_cli_stderr = cli_stderr


def test_command_line_slow_time_column_one_line_with_its_advice(tmp_path, capsys):
    path = _csv(tmp_path / "slow.csv", np.arange(20) * 1000.0, _coeffs())
    code, lines = _cli_stderr(["info", path], capsys)
    assert code == 0 and len(lines) == 1, lines
    assert lines[0].startswith("modalinfo info: warning: ") and "0.001 Hz" in lines[0]
    assert lines[0].endswith(f"({CLI_TIMES_ADVICE}).") and "filter" not in lines[0]


def test_command_line_rate_gets_the_option_advice(tmp_path, capsys):
    path = tmp_path / "log.npy"
    np.save(path, _coeffs(400))
    code, lines = _cli_stderr(["info", path, "--rate", "0.001"], capsys)
    assert code == 0 and len(lines) == 1, lines
    assert lines[0].endswith(f"({CLI_RATE_ADVICE}).") and "filter" not in lines[0]


def test_command_line_nanosecond_column_refused_without_warning(tmp_path, capsys):
    path = _csv(tmp_path / "ns.csv", np.arange(20) * 1e6, _coeffs())
    code, lines = _cli_stderr(["reorder", path], capsys)
    assert code == 2 and len(lines) == 1, lines
    assert "error" in lines[0] and "warning" not in lines[0]


# ---------------------------------------------------------------------- bins, 0-d string
@pytest.mark.parametrize("rule", ["auto", "hacine-gharbi"])
def test_bins_as_a_0d_string_array_is_its_rule(rule):
    x = np.random.default_rng(1).standard_normal((500, 2))
    want = mutual_information(x[:, 0], x[:, 1], method="histogram", bins=rule)
    got = mutual_information(x[:, 0], x[:, 1], method="histogram", bins=np.array(rule))
    assert got == want


def test_bins_0d_string_array_unknown_rule_refused_as_the_string():
    x = np.random.default_rng(1).standard_normal((100, 2))
    with pytest.raises(ValueError, match="`bins` must be one of .* got 'autox'"):
        mutual_information(x[:, 0], x[:, 1], method="histogram", bins=np.array("autox"))


def test_foreign_aot_file_with_times_1000_s_apart_warned(tmp_path):
    aotpy = pytest.importorskip("aotpy")
    tel = aotpy.MainTelescope(uid="TEL", enclosing_diameter=8.0)
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    wfs = aotpy.ShackHartmann(uid="WFS", source=ngs, n_valid_subapertures=6)
    dm = aotpy.DeformableMirror(uid="DM", telescope=tel, n_valid_actuators=40)
    time = aotpy.Time("t", timestamps=(np.arange(20) * 1000.0).tolist())
    loop = aotpy.ControlLoop(uid="L", input_sensor=wfs, commanded_corrector=dm, time=time,
                             modal_coefficients=aotpy.Image("c", _coeffs(), unit="rad",
                                                            time=time))
    system = aotpy.AOSystem(ao_mode="SCAO", name="T", main_telescope=tel, sources=[ngs],
                            wavefront_sensors=[wfs], wavefront_correctors=[dm], loops=[loop])
    path = tmp_path / "slow.fits"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # aotpy's notes on its empty tables
        system.write_to_file(str(path))
    log, _ = _one_warning(SLOW, load, path, fmt="aot")
    assert log.rate == pytest.approx(0.001)


def test_r0_warning_has_the_config_advice_on_a_command_line():
    from modalinfo.common.startup import command_line_text
    from modalinfo.common.validation import CLI_R0_ADVICE, check_r0

    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        check_r0(15.0)
    (w,) = rec
    assert str(w.message).endswith(f"({PYTHON_ADVICE}).")  # the Python caller's, as before
    line = command_line_text(w.message)
    assert line.endswith(f"({CLI_R0_ADVICE}).") and "filter" not in line
    assert line.startswith("`r0` = 15 m is beyond 1 m at 500 nm")
