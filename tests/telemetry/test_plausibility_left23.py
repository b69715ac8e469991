"""Plausibility bounds of the Python API (round 23 PART a, m1 m3 m8 m10 m12 m13 m39).

References, all from outside the code:

- the file readers' layout rule (a round trip: ``ModalLog(x)`` refuses an array exactly
  when ``modalinfo.io.load`` of the same array saved as ``.npy`` calls it transposed);
- the command line's ``--rate`` range, 1 mHz - 1 MHz (the API refuses the same values
  with the same words), and the frame rates of wavefront sensors, 1 Hz - 100 kHz
  (high-order WFSs 0.2-4 kHz, tip-tilt sensors ~10 kHz);
- site surveys of the Fried parameter at 500 nm (2-20 cm typical, 0.3 m exceptional at
  night, 5-15 cm by day), hence 1 mm (seeing of 100") - 1 m, and its wavelength law
  ``r0 ~ lambda**(6/5)`` (Fried 1966);
- the largest telescope, the ELT (39 m): 100 m at most; jet-stream winds (30-70 m/s,
  rarely 100 m/s): 100 m/s at most.

Each bound is tested on both sides. A warning is a ``UserWarning`` (the suite turns
warnings into errors, so ``pytest.warns`` / ``warnings.catch_warnings`` are explicit).
"""

from __future__ import annotations

import re
import sys
import warnings

import numpy as np
import pytest

from closedloop.config import SimulationConfig
from closedloop.presets import table1
from modalinfo.cli import main
from modalinfo.common.validation import RATE_RULE
from modalinfo.forecast import evaluate, make_predictor
from modalinfo.io import LogFormatError, load
from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.synthetic import Layer, open_loop_log


def _x(shape):
    return np.random.default_rng(0).standard_normal(shape)


def _no_warning(func, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return func(*args, **kwargs)


def _one_warning(match, func, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = func(*args, **kwargs)
    texts = [str(w.message) for w in caught if issubclass(w.category, UserWarning)]
    assert len(texts) == 1, texts
    assert re.search(match, texts[0]), texts[0]
    return out


# ------------------------------------------------------------------ m1: the layout
def test_m1_modes_by_frames_refused_naming_coeffs_and_the_fix():
    with pytest.raises(ValueError, match=r"`coeffs` of shape \(50, 400\) looks transposed"
                                         r".*pass coeffs\.T"):
        ModalLog(_x((50, 400)), rate=1000.0)


# both sides of each bound of the readers' rule: 64 columns (not > 64), 4 x rows, 5000
# (1300 rows: below 4 x rows, so only the 5000-column bound acts)
@pytest.mark.parametrize("shape", [(16, 64), (16, 65), (17, 67), (17, 68), (1300, 5000),
                                   (1300, 5001), (400, 50), (50, 50)])
def test_same_verdict_as_the_readers(shape, tmp_path):
    x = np.zeros(shape, dtype=np.float32)
    path = tmp_path / "x.npy"
    np.save(path, x)
    try:
        load(path)
        reader_refuses = False
    except LogFormatError:
        reader_refuses = True
    try:
        ModalLog(x)
        api_refuses = False
    except ValueError as exc:
        assert "coeffs.T" in str(exc)
        api_refuses = True
    assert api_refuses == reader_refuses
    assert reader_refuses == (shape in [(16, 65), (17, 68), (1300, 5001)])


def test_short_log_of_many_named_modes_kept():
    """A 4-m telescope's short log: 10 frames of 1,500 K-L modes, the columns named."""
    labels = [f"KL{k}" for k in range(1, 1501)]
    log = ModalLog(_x((10, 1500)), rate=2000.0, modes=labels, convention="labels")
    assert log.coeffs.shape == (10, 1500)
    log = ModalLog(_x((10, 1500)), modes=range(2, 1502))
    assert log.n_frames == 10
    log = ModalLog(_x((10, 1500)), timestamps=np.arange(10) / 2000.0)
    assert log.n_modes == 1500


def test_labelled_dataframe_confirms_the_layout():
    pd = pytest.importorskip("pandas")
    frame = pd.DataFrame(_x((10, 100)), columns=[f"Z{j}" for j in range(2, 102)])
    assert ModalLog(frame).n_modes == 100
    with pytest.raises(ValueError, match="looks transposed"):
        ModalLog(pd.DataFrame(_x((10, 100))))  # pandas' default 0..99 names nothing


def test_modes_or_timestamps_one_per_row_point_at_the_transpose():
    with pytest.raises(ValueError, match=r"`modes` names 50 modes, one per row.*coeffs\.T"):
        ModalLog(_x((50, 400)), modes=range(2, 52))
    with pytest.raises(ValueError, match=r"`timestamps` has 400 times, one per column"):
        ModalLog(_x((50, 400)), timestamps=np.arange(400) / 1e3)


def test_reader_hint_as_stored_still_loads(tmp_path):
    path = tmp_path / "wide.npy"
    np.save(path, _x((50, 400)))
    assert load(path, transpose=False).coeffs.shape == (50, 400)
    assert load(path, transpose=True).coeffs.shape == (400, 50)


# ------------------------------------------------------------ m3, m8, m39: the rate
def test_m39_rate_below_one_millihertz_refused_with_the_command_line_words():
    with pytest.raises(ValueError, match=r"`rate`.*got 0\.0005 \(a period of 0\.0005 s is "
                                         r"rate=2000\)") as info:
        ModalLog(_x((400, 5)), rate=1 / 2000)
    assert RATE_RULE in str(info.value)
    with pytest.raises(ValueError, match="`rate`"):
        ModalLog(_x((400, 5)), rate=1.1e6)


def test_m3_period_typed_as_rate_warned_once():
    log = _one_warning(r"`rate` = 0\.001 Hz is below 1 Hz.*rate=1000", ModalLog,
                       _x((400, 5)), rate=0.001)
    assert log.rate == 0.001  # an archive of averages is analysed as given
    _one_warning(r"above 100000 Hz", ModalLog, _x((400, 5)), rate=1.5e5)
    _one_warning(r"above 100000 Hz", ModalLog, _x((400, 5)), rate=1e6)


@pytest.mark.parametrize("rate", [1.0, 2000.0, 1e5])
def test_wavefront_sensor_rates_silent(rate):
    assert _no_warning(ModalLog, _x((400, 5)), rate=rate).rate == rate


def test_m8_open_loop_log_rate():
    layer = Layer(r0=0.1, wind_speed=10.0)
    with pytest.raises(ValueError, match=r"`rate`.*rate=2000"):
        open_loop_log(n_frames=64, rate=1 / 2000, diameter=4.0, layers=layer, seed=0)
    _one_warning(r"`rate` = 0\.001 Hz", open_loop_log, n_frames=64, rate=0.001,
                 diameter=4.0, layers=layer, seed=0)


def test_m39_evaluate_sees_only_a_warned_log():
    with pytest.raises(ValueError, match="`rate`"):
        evaluate([make_predictor("linear")], ModalLog(_x((400, 2)), rate=1 / 2000),
                 horizons=[1])


def _cli(argv) -> int:
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:  # argparse's refusals
        return exc.code


def test_command_line_rate_unchanged_or_one_warning_line(tmp_path, capsys):
    path = tmp_path / "log.npy"
    np.save(path, _x((400, 3)))
    assert _cli(["info", path, "--rate", "0.0005"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and RATE_RULE in err
    with warnings.catch_warnings():
        # as outside pytest, which records warnings (and the suite makes them errors):
        # Python's default showwarning writes formatwarning's text to stderr
        warnings.simplefilter("always")
        warnings.showwarning = lambda message, category, filename, lineno, file=None, \
            line=None: sys.stderr.write(warnings.formatwarning(message, category, filename,
                                                               lineno, line))
        assert _cli(["info", path, "--rate", "0.001"]) == 0
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("modalinfo info: warning: `rate`")
    assert "below 1 Hz" in lines[0]


# --------------------------------------------------------- m10, m12: r0 and the wind
def test_m10_r0_in_centimetres_warned():
    layer = _one_warning(r"`r0` = 15 m is beyond 1 m at 500 nm.*r0=0\.15", Layer,
                         r0=15, wind_speed=10.0)
    assert layer.r0 == 15.0  # kept: a weak layer of a many-layer profile


def test_m12_r0_and_wind_swapped_warned():
    _one_warning(r"`r0` = 10 m", Layer, r0=10, wind_speed=0.15)


@pytest.mark.parametrize("r0", [1e-3, 0.15, 1.0])
def test_site_r0_silent(r0):
    assert _no_warning(Layer, r0=r0, wind_speed=10.0).r0 == r0


def test_r0_bounds():
    _one_warning(r"beyond 1 m", Layer, r0=1.01, wind_speed=10.0)
    with pytest.raises(ValueError, match=r"`r0` must be >= 0\.001 m at 500 nm"):
        Layer(r0=9e-4, wind_speed=10.0)


def test_r0_bound_scales_as_lambda_to_the_six_fifths():
    """At 2.2 um the 1 m bound at 500 nm is (2.2 / 0.5)**1.2 = 5.92 m (Fried 1966)."""
    bound = (2.2e-6 / 500e-9) ** 1.2
    assert _no_warning(Layer, r0=0.99 * bound, wind_speed=10.0, r0_wavelength=2.2e-6)
    _one_warning(r"m at 500 nm", Layer, r0=1.01 * bound, wind_speed=10.0,
                 r0_wavelength=2.2e-6)


def test_wind_bounds():
    assert _no_warning(Layer, r0=0.1, wind_speed=100.0).wind_speed == 100.0
    assert _no_warning(Layer, r0=0.1, wind_speed=0.15).wind_speed == 0.15
    with pytest.raises(ValueError, match=r"`wind_speed` must be <= 100 m/s.*km/h"):
        Layer(r0=0.1, wind_speed=100.5)


# ----------------------------------------------------------------- m13: the diameter
def test_m13_diameter_in_centimetres_refused_as_closedloop_does():
    layer = Layer(r0=0.1, wind_speed=10.0)
    with pytest.raises(ValueError, match=r"`diameter` must be <= 100 m") as api:
        open_loop_log(n_frames=64, rate=1000.0, diameter=800.0, layers=layer, seed=0)
    plain = table1().to_dict()
    plain["telescope"]["diameter"] = 800.0
    with pytest.raises(ValueError) as config:
        SimulationConfig.from_dict(plain)
    # one rule: the same sentence after the argument's name
    assert str(api.value).split("` ", 1)[1] == str(config.value).split("` ", 1)[1]


def test_largest_diameter_kept():
    log = _no_warning(open_loop_log, [2, 3], n_frames=64, rate=1000.0, diameter=100.0,
                      layers=Layer(r0=0.1, wind_speed=10.0), seed=0)
    assert log.metadata["diameter_m"] == 100.0


def test_a_file_keeps_its_stored_rate_without_a_warning_on_every_read(tmp_path):
    """An archive of one frame a minute, written once with its warning, reads silently."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        log = ModalLog(_x((400, 3)), rate=1 / 60)
    for ext in ("npz", "h5"):
        path = tmp_path / f"archive.{ext}"
        from modalinfo.io import save

        save(log, path)
        assert _no_warning(load, path).rate == pytest.approx(1 / 60, rel=1e-15)


def test_warnings_point_at_the_callers_line():
    """Python's convention: a warning names the line of the user's call, however deep."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        open_loop_log(n_frames=64, rate=0.001, diameter=4.0,
                      layers=Layer(r0=15, wind_speed=10.0), seed=0)
    assert [w.filename for w in caught] == [__file__, __file__]
