"""The MI-gain block bootstrap never joins frames that a drop made look adjacent.

References (outside the code under test): the block bootstrap's definition (Kuensch
1989; Politis & Romano 1992: blocks of *consecutive* frames), so a log whose removed
frames left no trace in its time axis cannot be resampled in blocks and is refused in
one sentence naming the removal, while the same log with a rate shows the removal as a
gap (the existing gap rule) and with ``n_resamples=0`` (no blocks) is ordered as before;
the command line's one-line refusal contract (exit 2).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.telemetry import ModalLog, apply_outlier_policy

KW = {"sample_budget": 2000, "seed": 0}


@pytest.fixture(scope="module")
def data():
    x = np.random.default_rng(5).standard_normal((300, 5)) * np.array([3, 2, 1.5, 1, 0.5])
    return x


@pytest.fixture(scope="module")
def basis():
    return ZernikeBasis(Pupil(16), range(2, 7))


def test_frames_dropped_as_nonfinite_without_a_rate_are_refused(data, basis):
    x = data.copy()
    x[100:102, 0] = np.nan
    log = ModalLog(x, modes=range(2, 7), nonfinite="drop")  # no rate: 298 frames, no trace
    assert log.n_frames == 298 and log.timestamps is None
    with pytest.raises(ValueError, match=r"^the block bootstrap of the MI gains .* takes the "
                                         r"frames as consecutive, but frames were removed .*"
                                         r"dropped 2 frame\(s\)"):
        order_modes(log, basis, "mi_greedy", n_resamples=5, **KW)
    # no blocks, no refusal: the pooled MI treats the frames as one sample
    kept = order_modes(log, basis, "mi_greedy", n_resamples=0, **KW)
    same = order_modes(np.delete(x, [100, 101], axis=0), basis, "mi_greedy", n_resamples=0,
                       **KW)
    assert kept.labels == same.labels
    # with a rate the removal is a gap, refused by the gap rule (names the gap)
    with pytest.raises(ValueError, match=r"timestamps have"):
        order_modes(ModalLog(x, modes=range(2, 7), nonfinite="drop", rate=1000.0), basis,
                    "mi_greedy", n_resamples=5, **KW)


def test_frames_dropped_by_the_outlier_policy_without_a_rate_are_refused(data, basis):
    x = data.copy()
    x[150] += 100.0  # a glitched frame, every mode
    dropped, report = apply_outlier_policy(ModalLog(x, modes=range(2, 7)), "drop")
    assert report.flagged_frames.tolist() == [150] and dropped.n_frames == 299
    with pytest.raises(ValueError, match=r"frames were removed .*dropped 1 of 300 frames "
                                         r"\(outlier policy 'drop'\)"):
        order_modes(dropped, basis, "mi_marginal", n_resamples=5, **KW)


def test_reorder_refuses_in_one_line(tmp_path, capsys):
    from tests.cli.conftest import exit_code

    data = np.random.default_rng(7).standard_normal((300, 2))
    data[100:102, 0] = np.nan
    path = tmp_path / "nan.csv"
    path.write_text("\n".join(["Z2,Z3"] + [f"{a!r},{b!r}" for a, b in data.tolist()]) + "\n")
    base = ["reorder", path, "--nonfinite", "drop", "--pupil-pixels", "16", "--budget",
            "500"]
    assert exit_code([*base, "--resamples", "5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "without a time axis" in err[0], err
    assert exit_code([*base, "--resamples", "0"]) == 0
    capsys.readouterr()
