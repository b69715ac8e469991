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


def _zernike_log(tmp_path):
    """15 AR(1) Zernike modes Z2..Z16 (radial orders 1..5); Z5 <- Z3 one frame later."""
    rng = np.random.default_rng(4)
    x = lfilter([1.0], [1.0, -0.6], rng.standard_normal((1500, 15)), axis=0)
    x[1:, 3] += 0.5 * x[:-1, 1]
    path = tmp_path / "zern.npz"
    save(ModalLog(x, rate=1000.0, modes=list(range(2, 17))), path)
    return path


def test_select_radial_candidates_print_the_library_table(tmp_path, capsys):
    path = _zernike_log(tmp_path)
    argv = ["--target", "Z5", "--max-lag", "3", "--surrogates", "19", "--no-intervals"]
    assert main(["select", str(path), *argv, "--candidates", "radial",
                 "--radial-width", "1"]) == 0
    text = capsys.readouterr().out
    ref = select_inputs(load(path), "Z5", max_lag=3, n_surrogates=19, intervals=False,
                        seed=0, candidates="radial", radial_width=1)
    assert text.strip() == ref.table().strip()
    # Z5 is radial order 2: orders 1..3 are Z2..Z10 (Noll 1976), 9 modes x 3 lags
    assert "27 candidates" in text and ref.n_candidates == 27
    # the default width 2: orders 0..4, Z2..Z15 (Z16 is order 5), 14 modes x 3 lags
    assert main(["select", str(path), *argv, "--candidates", "radial"]) == 0
    assert "42 candidates" in capsys.readouterr().out


def test_select_candidate_errors_are_one_line(tmp_path, capsys):
    path = _zernike_log(tmp_path)
    labelled = tmp_path / "labelled.npz"
    save(ModalLog(np.random.default_rng(0).standard_normal((300, 2)), rate=1000.0,
                  modes=["a", "b"], convention="labels"), labelled)
    for log, argv, words in [
        (path, ["--candidates", "radial", "--radial-width", "-1"],
         "--radial-width must be an int >= 0; got -1"),
        (path, ["--radial-width", "1"], "--radial-width 1 applies to --candidates radial"),
        (path, ["--candidates", "nearby"], "invalid choice: 'nearby'"),
        (labelled, ["--candidates", "radial"], "needs Zernike (Z<j>, Noll) or K-L"),
    ]:
        target = "a" if log == labelled else "Z5"
        try:
            code = main(["select", str(log), "--target", target, *argv])
        except SystemExit as exc:  # argparse's usage errors (the shared Parser: one line)
            code = exc.code
        assert code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and words in err[0], err


def test_select_slow_method_is_told_or_refused_before_work(tmp_path, capsys, monkeypatch):
    """Audit 9: ``--method ksg`` ran 9.6 min of wall time without a word. Reference: the
    library's first-step estimate (m (1 + N) KSG CMIs, ``ksg_cost`` each) stated before
    the search, and a refusal above ``--max-seconds`` (exit 2, one line)."""
    from modalinfo.information import selection

    p1, _ = _logs(tmp_path)
    assert main(["select", str(p1), "--target", "Z5", "--method", "ksg", "--no-intervals",
                 "--max-seconds", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "would take about" in err[-1] and "--max-seconds=1" in err[-1]
    assert main(["select", str(p1), "--target", "Z5", "--max-seconds", "-1"]) == 2
    assert "--max-seconds must be > 0" in capsys.readouterr().err

    def stop(*args, **kwargs):  # the note must come before the search
        raise SystemExit(5)

    monkeypatch.setattr(selection, "_greedy_search", stop)
    try:
        main(["select", str(p1), "--target", "Z5", "--method", "ksg", "--no-intervals"])
    except SystemExit as exc:
        assert exc.code == 5
    err = capsys.readouterr().err
    assert "note: --method ksg scores 20 candidates x 200" in err and "s of CPU" in err


def test_extra_of_the_same_clock_with_timing_noise_accepted(tmp_path, capsys):
    # Reference: both logs time the same 2 kHz frames, each with 2 % timing noise (their
    # mean rates differ by ~1e-5, which was refused as "2000.02 Hz, LOG at 2000.02 Hz";
    # audit 10-time); an extra log 2 s later is still refused, frame by frame.
    rng = np.random.default_rng(7)
    t = np.arange(3000) / 2000.0
    for name in ("a", "b", "late"):
        times = np.sort(t + rng.normal(0, 0.02 / 2000, t.size)) + (2.0 if name == "late" else 0)
        save(ModalLog(rng.standard_normal((3000, 2)), timestamps=times,
                      modes=[2, 3] if name == "a" else [5, 6]), tmp_path / f"{name}.npz")
    args = ["select", str(tmp_path / "a.npz"), "--target", "Z2", "--max-lag", "2"]
    assert main([*args, "--extra", str(tmp_path / "b.npz")]) == 0
    capsys.readouterr()
    assert main([*args, "--extra", str(tmp_path / "late.npz")]) == 2
    assert "must be sampled at the frames" in capsys.readouterr().err
