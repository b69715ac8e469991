"""Round 45 PART b's thresholds' messages and digits of other scripts (fixes 45-c).

References, from outside the code: each rule's own arithmetic by hand (the bootstrap's
R (1 - L) / 2 replicates per tail and (R - 1) / (R + 1) coverage of the replicates'
range; select's horizon + max_lag + 19 frames; dPhi <= F x dPhi(0) at F = 0.9999999999);
Python's ``str.isdecimal`` / ``unicodedata`` for the superscript digits and the dashes.
"""

from __future__ import annotations

import unicodedata

import numpy as np
import pytest

from modalinfo.bases.indexing import parse_modes
from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code, write_small_log


def test_reorder_caution_at_39_replicates_states_a_reason_that_holds(tmp_path, capsys):
    # T36: "their whole range covers 95% at most" at 39, where (39 - 1) / (39 + 1) is
    # exactly 95 %; what fails at 39 is the tail: 39 x 0.05 / 2 = 0.975 < 1 replicate
    log = write_small_log(tmp_path / "log.npz", 400)
    base = ["reorder", log, "--pupil-pixels", "16", "--budget", "500"]
    assert exit_code([*base, "--resamples", "39"]) == 0
    out = capsys.readouterr().out
    assert ("caution: 39 replicates are too few for 95% bounds: 39 x 0.05 / 2 = 0.975 "
            "replicate(s) per tail, fewer than 1") in out
    assert "(39 - 1) / (39 + 1) = 95% at most" in out
    assert exit_code([*base, "--resamples", "2"]) == 0
    out = capsys.readouterr().out  # 2 x 0.05 / 2 = 0.05; 1 / 3 = 33.33 %
    assert "2 x 0.05 / 2 = 0.05 replicate(s)" in out and "= 33.33% at most" in out


def test_reorder_split_gaps_help_says_when_the_default_refuses(tmp_path, capsys):
    # T54: the help said "default: refuse the log" while the pooled ordering (--resamples
    # 0) runs a 10 x gap without a word, rightly; the help now names what refuses it
    assert exit_code(["reorder", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert ("default: refuse the log when the block bootstrap of the gains (--resamples > 0 "
            "with an mi_ method on all frames) or --stability needs equally spaced frames; "
            "the pooled ordering itself does not") in text
    t = np.arange(300) / 2000.0
    t[150:] += 9 / 2000.0  # one interval 10 x the median
    coeffs = np.random.default_rng(2).standard_normal((300, 3))
    log = save(ModalLog(coeffs, timestamps=t, modes=[2, 3, 4], units="rad"),
               tmp_path / "gap.npz")
    base = ["reorder", log, "--pupil-pixels", "16", "--budget", "500"]
    assert exit_code([*base, "--resamples", "0"]) == 0  # as the help says
    capsys.readouterr()
    assert exit_code([*base, "--resamples", "40"]) == 2  # the bootstrap refuses it
    assert "--split-gaps" in capsys.readouterr().err


def test_select_max_frames_refusal_names_the_option(tmp_path, capsys):
    # T74: "the log needs at least 22 frames ...; got 12" of a 400-frame log; by hand
    # horizon 1 + max_lag 2 + 19 = 22 frames (20 rows of lagged pairs)
    log = write_small_log(tmp_path / "log.npz", 400)
    argv = ["select", log, "--target", "Z2", "--max-lag", "2", "--no-intervals",
            "--surrogates", "9", "--alpha", "0.2"]  # 9 shifts fit in 20 rows (the pairs'
    # rule binds; 199 need 210 rows: tests/cli/test_select_max_frames_surrogates_lead53.py)
    assert exit_code([*argv, "--max-frames", "12"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert ("--max-frames 12 leaves 12 of the 400 frames of 'log.npz'; --horizon 1 and "
            "--max-lag 2 need at least 22") in err and "give --max-frames 22 or more" in err
    assert exit_code([*argv, "--max-frames", "21"]) == 2
    assert "--max-frames 21 leaves 21" in capsys.readouterr().err
    # a log that is short by itself keeps the library's words (no --max-frames cut)
    short = write_small_log(tmp_path / "short.npz", 12)
    assert exit_code(["select", short, "--target", "Z2", "--max-lag", "2",
                      "--no-intervals"]) == 2
    err = capsys.readouterr().err
    assert "needs at least 22 frames" in err and "--max-frames" not in err


def test_fitting_error_fraction_label_tells_it_from_100_percent(tmp_path, capsys):
    # T81: --fraction 0.9999999999 was labelled "<=100%" (.3g), a bound no mode meets;
    # the rule applied is dPhi <= 99.99999999 % of dPhi(0)
    log = write_small_log(tmp_path / "log.npz", 300)
    assert exit_code(["fitting-error", log, "--orderings", "zernike:standard",
                      "--pupil-pixels", "16", "--fraction", "0.9999999999"]) == 0
    head = capsys.readouterr().out.splitlines()[1].split()
    assert head[-1] == "<=99.99999999%"
    assert exit_code(["fitting-error", log, "--orderings", "zernike:standard",
                      "--pupil-pixels", "16", "--fraction", "0.5"]) == 0
    assert capsys.readouterr().out.splitlines()[1].split()[-1] == "<=50%"  # as before


@pytest.mark.parametrize(("text", "odd"), [("²-⁶", "²"), ("²,³", "²"), ("3,⁵", "⁵")])
def test_superscript_digits_are_refused_naming_the_argument(text, odd):
    # Y12 / Y17: str.isdigit() is true for superscripts, which int() refuses ("invalid
    # literal for int() with base 10"); isdecimal() is what int() reads
    assert odd.isdigit() and not odd.isdecimal()
    with pytest.raises(ValueError, match=rf"^--in-modes: .* holds '{odd}' "
                                         rf"\(U\+{ord(odd):04X}, "
                                         rf"{unicodedata.name(odd).lower()}\)"):
        parse_modes(text, "--in-modes")


def test_other_scripts_decimal_digits_are_still_read():
    # round 44 PART b (a01) and round 45 Y11 / Y16: int() reads them; so does the parser
    assert parse_modes("２-６") == [2, 3, 4, 5, 6]
    assert parse_modes("٢,٣") == [2, 3]
    assert parse_modes("Z2,Z²") == ["Z2", "Z²"]  # a label with a superscript stays a label


@pytest.mark.parametrize("dash", ["\u2013", "\u2212", "\u2010", "\u2014"])
def test_a_range_written_with_another_dash_is_refused_naming_it(dash):
    # Y26: '2–6' (an en dash, as a word processor types it) was read as one label
    with pytest.raises(ValueError, match=rf"'2{dash}6' joins mode indices with "
                                         rf"U\+{ord(dash):04X} \("):
        parse_modes(f"2{dash}6", "--in-modes")
    assert parse_modes("Tip\u2013Tilt") == ["Tip\u2013Tilt"]  # a label keeps its dash


def test_cli_superscript_target_and_en_dash_range(tmp_path, capsys):
    # Y14: select --target ³ reached int(); Y26: info --in-modes 2–4 blamed a convention
    log = write_small_log(tmp_path / "log.npz", 400)
    assert exit_code(["select", log, "--target", "³", "--max-lag", "2",
                      "--no-intervals"]) == 2
    err = capsys.readouterr().err
    assert "--target '³' is not a mode of LOG" in err and "int()" not in err
    assert exit_code(["info", log, "--in-modes", "2\u20134", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "--in-modes: '2\u20134' joins mode indices with U+2013 (en dash)" in err
    assert "write '2-4'" in err
