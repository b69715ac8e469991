"""A spike, a stuck run and pairs swapped in part of a log are named by row
(adversarial round 37 PART b, P02, P03, P10; issue 27, fix38-c).

References, from outside the code: the planted rows, found back with numpy on the
planted array against the clean one (``numpy.flatnonzero`` of the changed rows; the run
of equal values of ``numpy.diff``; the rows whose order differs), and the mode labels
of the Noll convention (column j holds Z(j + 2)). Before the fix a single-mode spike
read "(most: Z6 1)" with no row, a stuck run "40 stuck value(s) ... in 1 mode(s)" with
neither mode nor row, and pairs swapped in rows 2000..3999 only "the frames of each pair
2k, 2k + 1 look written in reverse order" of the whole log; ``info``, the warning and
``batch``'s row (``QualityReport.columns``) carry the same words.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog, assess_quality

MODES = list(range(2, 14))  # Z2 .. Z13: column j is Z(j + 2)


def _ar1(n: int, m: int, rho: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.normal(size=(n, m)) * np.sqrt(1 - rho**2)
    e[0] = rng.normal(size=m)
    return lfilter([1.0], [1.0, -rho], e, axis=0)


def _log(y: np.ndarray) -> ModalLog:
    return ModalLog(y, rate=1000.0, modes=MODES, wavelength=5e-7)


def _swap_pairs(x: np.ndarray, start: int, stop: int) -> np.ndarray:
    y = x.copy()
    y[start:stop:2], y[start + 1:stop:2] = x[start + 1:stop:2], x[start:stop:2]
    return y


def test_a_single_mode_spike_is_named_by_row():
    x = _ar1(4000, len(MODES), 0.9, 3)
    y = x.copy()
    y[2000, MODES.index(6)] += 40.0  # 40 sigma in Z6 at row 2000
    rows = np.flatnonzero(np.any(y != x, axis=1))
    assert rows.tolist() == [2000]
    report = assess_quality(_log(y))
    assert report.outlier_frames.tolist() == rows.tolist()
    assert "1 outlier value(s) in 1 frame(s) (frames 2000; most: Z6 1)" in report.describe()
    assert report.columns()["quality_outlier_rows"] == "2000"


def test_many_spikes_name_the_first_five_rows():
    x = _ar1(4000, len(MODES), 0.9, 4)
    y = x.copy()
    planted = [300, 900, 1500, 2100, 2700, 3300, 3900]
    y[planted, MODES.index(5)] += 40.0
    rows = np.flatnonzero(np.any(y != x, axis=1))
    report = assess_quality(_log(y))
    shown = ", ".join(str(r) for r in rows[:5]) + ", ..."
    assert f"(frames {shown}; most: Z5 7)" in report.describe()
    assert report.to_dict()["outlier_rows"] == shown


def test_a_stuck_run_is_named_by_mode_and_rows():
    x = _ar1(4000, len(MODES), 0.9, 5)
    y = x.copy()
    j = MODES.index(9)
    y[1500:1540, j] = y[1500, j]  # Z9 held over rows 1500..1539
    held = np.flatnonzero(np.diff(y[:, j]) == 0)  # rows t with y[t + 1] == y[t]
    first, last = int(held[0]), int(held[-1]) + 1
    assert (first, last) == (1500, 1539)
    report = assess_quality(_log(y))
    text = report.describe()
    assert "40 stuck value(s)" in text
    words = f"most: Z9 40; the first: Z9 rows {first}..{last}"
    assert f"({words})" in text
    assert report.columns()["quality_stuck_rows"] == words
    assert report.stuck_block == (first, last + 1, ("Z9",))


def test_pairs_swapped_in_the_second_half_are_named_with_their_rows():
    x = _ar1(4000, len(MODES), 0.9, 6)
    y = _swap_pairs(x, 2000, 4000)
    moved = np.flatnonzero(np.any(y != x, axis=1))
    start, stop = int(moved[0]), int(moved[-1]) + 1
    assert (start, stop) == (2000, 4000)
    report = assess_quality(_log(y))
    assert report.pair_order and report.pair_rows == (start, stop)
    text = report.describe()
    assert f"in rows {start}..{stop - 1} (to the rule's 32 batches" in text
    assert report.columns()["quality_pair_order"].endswith(f", rows {start}..{stop - 1}")


def test_pairs_swapped_in_a_middle_stretch():
    x = _ar1(4000, len(MODES), 0.9, 7)
    y = _swap_pairs(x, 1000, 3000)  # both ends on the rule's batch edges (125 frames)
    report = assess_quality(_log(y))
    assert report.pair_order and report.pair_rows == (1000, 3000)
    assert "in rows 1000..2999 (" in report.describe()


def test_pairs_swapped_in_the_whole_log_keep_the_whole_log_words():
    x = _ar1(4000, len(MODES), 0.9, 8)
    report = assess_quality(_log(_swap_pairs(x, 0, 4000)))
    assert report.pair_order and report.pair_rows == ()
    assert "in rows" not in report.pair_note
    assert ", rows" not in report.columns()["quality_pair_order"]


def test_info_names_the_rows(tmp_path, capsys):
    x = _ar1(4000, len(MODES), 0.9, 3)
    y = x.copy()
    y[2000, MODES.index(6)] += 40.0
    y[1500:1540, MODES.index(9)] = y[1500, MODES.index(9)]
    save(_log(y), tmp_path / "p.npz")
    assert main(["info", str(tmp_path / "p.npz")]) == 0
    out = capsys.readouterr()
    text = out.out + out.err
    assert "frames 2000; most: Z6 1" in text
    assert "the first: Z9 rows 1500..1539" in text


@pytest.mark.parametrize("seed", [11, 12])
def test_a_clean_log_names_nothing(seed):
    report = assess_quality(_log(_ar1(4000, len(MODES), 0.9, seed)))
    cols = report.columns()
    assert report.clean
    assert cols["quality_outlier_rows"] == cols["quality_stuck_rows"] == ""
    assert cols["quality_pair_order"] == ""
