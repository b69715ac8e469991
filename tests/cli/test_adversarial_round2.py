"""Round 2 of issue 27's adversarial inputs: the ones that failed, fixed at the entry.

The full list of inputs tried (input | expected | observed before | after) is in
docs/ADVERSARIAL.md, section "Round 2, issue 27".

References: the dispatcher's documented contract (one line on stderr naming the
option, exit 2, no traceback); for the summary of a log of tiny values, the
statistics of the same values before an exact power-of-two scaling (``x * 2**-1000``
is exact in float64 for these magnitudes, and mean, std and RMS scale with it),
computed by NumPy on the unscaled array.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.telemetry.summary import summarize

from .conftest import exit_code


@pytest.fixture
def small_log(make_small_log):
    return make_small_log(300)


@pytest.mark.parametrize("value", ["nan", "inf"])
def test_fitting_error_target_not_finite_is_refused_naming_target(small_log, capsys, value):
    # Before: --target nan ran the work and failed with "`error` must be finite".
    assert exit_code(["fitting-error", str(small_log), f"--target={value}", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert "--target" in err and "finite" in err, err


@pytest.mark.parametrize("exponent", [-1000, -600, 0])
def test_summary_of_tiny_values_is_not_zero(exponent):
    # Before: values of 1e-300 had RMS 0 and std 0 (their squares underflow).
    rng = np.random.default_rng(1)
    base = rng.standard_normal((500, 3)) + 0.1
    scale = 2.0 ** exponent
    got = summarize(base * scale)
    np.testing.assert_allclose(got.rms / scale, np.sqrt(np.mean(base**2, axis=0)),
                               rtol=1e-12)
    np.testing.assert_allclose(got.std / scale, base.std(axis=0), rtol=1e-12)
    np.testing.assert_allclose(got.mean / scale, base.mean(axis=0), rtol=1e-12)
    c = base - base.mean(axis=0)
    lag1 = np.sum(c[:-1] * c[1:], axis=0) / np.sum(c**2, axis=0)  # the sample ACF at lag 1
    np.testing.assert_allclose(got.lag1, lag1, rtol=1e-9)


@pytest.mark.parametrize("argv", [
    ["modalinfo", "select", "LOG", "--target", "Z2", "--target", "Z3"],
    ["modalinfo", "info", "LOG", "--rate=2000", "--rate", "1000"],
    ["closedloop", "config", "--preset", "table1", "--preset", "kaos"],
    ["paper_figures", "--seed", "1", "--seed=2"],
])
def test_an_option_given_twice_with_different_values_is_refused(small_log, capsys, argv):
    # Before: argparse kept the last value silently (select analysed Z3).
    from closedloop.cli import main as closedloop_main
    from paper_figures.__main__ import main as figures_main

    run = {"modalinfo": main, "closedloop": closedloop_main, "paper_figures": figures_main}
    argv = [str(small_log) if a == "LOG" else a for a in argv]
    assert _exit_code_of(run[argv[0]], argv[1:]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert "given twice" in err and argv[-1].split("=")[0] in err, err


def test_an_option_repeated_with_the_same_value_still_runs(small_log, capsys):
    assert exit_code(["info", str(small_log), "--rate=2000", "--rate", "2000",
                      "--quiet"]) == 0
    assert "given twice" not in capsys.readouterr().err


def _exit_code_of(func, argv):
    try:
        return func(argv)
    except SystemExit as exc:
        return exc.code


@pytest.mark.parametrize("rate", ["1e300", "inf", "nan", "0", "-1000", "1e-4", "2e6"])
def test_rate_outside_the_physical_range_is_refused_before_work(small_log, rate, capsys):
    # Reference: the documented range RATE_RANGE, 1 mHz - 1 MHz (modalinfo.cli.shared):
    # a --rate of 1e300 Hz used to be accepted and printed back as "1e+300 Hz".
    assert exit_code(["info", str(small_log), f"--rate={rate}"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--rate" in err and "hertz within 0.001 - 1e+06" in err


# 0.001 and 1e6 lie outside the wavefront sensors' 1 Hz - 100 kHz: accepted with a
# one-line UserWarning (Leftovers 23-plaus), which the suite would make an error
@pytest.mark.filterwarnings("ignore:`rate` = .* Hz is (below|above):UserWarning")
@pytest.mark.parametrize("rate", ["0.001", "2000", "1e6"])
def test_rate_inside_the_range_is_accepted(tmp_path, rate, capsys):
    path = tmp_path / "norate.npy"  # a bare array: no stored rate to contradict
    np.save(path, np.random.default_rng(1).standard_normal((300, 3)))
    assert exit_code(["info", str(path), "--modes", "2-4", f"--rate={rate}"]) == 0
    assert f"{float(rate):g} Hz" in capsys.readouterr().out
