"""Tests of ``modalinfo select``.

Reference: the table printed by :func:`modalinfo.information.select_inputs` called
directly on the log loaded with ``modalinfo.io.load`` (same text), the planted lag of
a frozen-flow pair split over two logs (``--extra``), and the dispatcher's documented
exit status 2 with a one-line error on bad input.
"""

import numpy as np
from scipy.signal import lfilter

from modalinfo.cli import main
from modalinfo.information import select_inputs
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog


def _logs(tmp_path, delay=6):
    rng = np.random.default_rng(0)
    n = 3000
    a = lfilter([1.0], [1.0, -0.95], rng.standard_normal(n + delay))
    b = a[:-delay] + 0.3 * rng.standard_normal(n)
    main_log = ModalLog(np.column_stack([b, rng.standard_normal(n)]), rate=1000.0,
                        modes=[5, 6])
    other = ModalLog(a[delay:, None], rate=1000.0, modes=[2])
    p1, p2 = tmp_path / "wfs1.npz", tmp_path / "wfs2.npz"
    save(main_log, p1)
    save(other, p2)
    return p1, p2


def test_select_prints_the_library_table(tmp_path, capsys):
    p1, _ = _logs(tmp_path)
    code = main(["select", str(p1), "--target", "Z5", "--horizon", "2", "--max-lag", "8",
                 "--surrogates", "39", "--no-intervals"])
    assert code == 0
    text = capsys.readouterr().out
    ref = select_inputs(load(p1), "Z5", horizon=2, max_lag=8, n_surrogates=39,
                        intervals=False, seed=0)
    assert text.strip() == ref.table().strip()


def test_select_finds_the_upstream_lag_in_the_extra_log(tmp_path, capsys):
    p1, p2 = _logs(tmp_path, delay=6)
    assert main(["select", str(p1), "--target", "Z5", "--horizon", "2", "--max-lag", "8",
                 "--extra", str(p2), "--surrogates", "39"]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert rows[2].split()[1] == "extra:Z2[t-4]"  # b[t+2] = a[t+2-6]


def test_select_errors_are_one_line(tmp_path, capsys):
    p1, _ = _logs(tmp_path)
    short = tmp_path / "short.npz"
    save(ModalLog(np.zeros((100, 1)) + np.arange(100)[:, None], rate=1000.0), short)
    for argv, words in [
        (["--target", "Z9"], "--target 'Z9' is not a mode of LOG"),
        (["--target", "7"], "--target column 7 is out of range"),
        (["--target", "Z5", "--extra", str(short)], "the two logs must share the clock"),
        (["--target", "Z5", "--horizon", "0"], "--horizon must be an int >= 1"),
        (["--target", "Z5", "--max-lag", "0"], "--max-lag must be an int >= 1"),
        (["--target", "Z5", "--surrogates", "0"], "--surrogates must be an int >= 1"),
    ]:
        assert main(["select", str(p1), *argv]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and words in err[0], err
