"""Tests of modalinfo.cli.shared: the frame rate a log gives is held to --rate's range.

Reference: the range ``--rate`` documents (1 mHz - 1 MHz, ``RATE_RANGE``) and a CSV
whose ``time`` column holds Unix nanoseconds at 2 kHz (5e5 ns steps): read as seconds
it gives 2e-6 Hz. Adversarial round 5, row i26 (analysed without a word before).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import main


@pytest.fixture
def ns_csv(tmp_path):
    rng = np.random.default_rng(0)
    t = 1.7e18 + np.arange(300) * 5e5  # Unix time in ns, 2 kHz
    data = rng.standard_normal((300, 2))
    rows = zip(t.tolist(), data.tolist(), strict=True)
    lines = ["time,Z2,Z3"] + [f"{a!r},{b!r},{c!r}" for a, (b, c) in rows]
    path = tmp_path / "ns.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def test_timestamps_giving_a_rate_outside_the_range_are_refused(ns_csv, capsys):
    code = main(["select", str(ns_csv), "--target", "Z2", "--max-lag", "2",
                 "--surrogates", "19", "--no-intervals"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "frame rate of 2e-06 Hz" in err and "--rate" in err


def test_an_explicit_rate_replaces_those_timestamps(ns_csv, capsys):
    code = main(["select", str(ns_csv), "--target", "Z2", "--max-lag", "2",
                 "--surrogates", "19", "--no-intervals", "--rate", "2000"])
    assert code == 0, capsys.readouterr().err


def test_a_fifo_given_as_the_log_is_named_a_fifo(tmp_path, capsys):
    # round 5, row g04: `paper_figures --log fifo.npz` said "log file ... does not exist"
    import os

    from modalinfo.cli import CommandError
    from modalinfo.cli.shared import load_log_with_hints

    fifo = tmp_path / "log.npz"
    os.mkfifo(fifo)
    with pytest.raises(CommandError, match=r"'.*log\.npz' is a FIFO, not a regular file"):
        load_log_with_hints(fifo)
    with pytest.raises(CommandError, match="does not exist"):
        load_log_with_hints(tmp_path / "missing.npz")
