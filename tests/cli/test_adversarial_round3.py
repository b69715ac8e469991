"""Round 3 of issue 27's adversarial inputs: the ones that failed, fixed at the entry.

The full list of inputs tried (id | input | expected | observed | verdict | fix) is in
docs/ADVERSARIAL.md, section "Round 3, issue 27".

References: the dispatcher's documented contract (one line on stderr naming the
option and the rule, exit 2, no traceback, nothing written or overwritten); the
extension table ``LOG_SUFFIXES`` of the README ("the output format comes from OUT's
extension"); for the glitched log, the ordering of the same log without the glitch
(same seed, same samples), as in tests/ordering/test_glitch_robustness.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def small_log(make_small_log):
    return make_small_log(300)


def _one_line(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


# ------------------------------------------------------------ --to-fmt vs the extension
@pytest.mark.parametrize("name, fmt", [
    ("out.csv", "npz"), ("out.npz", "csv"), ("out.h5", "fits"), ("out.fits", "hdf5"),
    ("out.hdf5", "aot"), ("out.FIT", "npz"),
])
def test_convert_to_fmt_contradicting_the_extension_is_refused(small_log, tmp_path, capsys,
                                                               name, fmt):
    # Before: `convert --to-fmt npz out.csv` wrote NPZ bytes under a .csv name, exit 0.
    out = tmp_path / name
    assert exit_code(["convert", small_log, out, "--to-fmt", fmt, "--quiet"]) == 2
    err = _one_line(capsys)
    assert f"--to-fmt {fmt} contradicts OUT" in err, err
    assert not out.exists()


def test_synth_to_fmt_contradicting_the_extension_is_refused(tmp_path, capsys):
    out = tmp_path / "s.csv"
    assert exit_code(["synth", out, "--frames", "50", "--to-fmt", "npz", "--quiet"]) == 2
    assert "--to-fmt npz contradicts OUT" in _one_line(capsys)
    assert not out.exists()


@pytest.mark.parametrize("name, fmt, kind", [
    ("out.npz", "npz", "npz"), ("out.fits", "aot", "aot"), ("out.fts", "fits", "fits"),
    ("out.dat", "csv", "csv"),
])
def test_to_fmt_agreeing_with_or_naming_the_extension_still_writes(small_log, tmp_path,
                                                                   capsys, name, fmt, kind):
    out = tmp_path / name
    assert exit_code(["convert", small_log, out, "--to-fmt", fmt, "--quiet"]) == 0
    back = load(out, fmt=kind)
    np.testing.assert_array_equal(back.coeffs, load(small_log).coeffs)


# ------------------------------------------------------------ batch --analyses twice
def test_batch_analyses_named_twice_is_refused_before_any_work(small_log, tmp_path, capsys):
    # Before: `--analyses summary,summary` merged the two silently (exit 0, one row).
    pytest.importorskip("distributed")
    out = tmp_path / "out"
    assert exit_code(["batch", small_log, "--out", out, "--analyses", "summary,summary",
                      "--quiet"]) == 2
    err = _one_line(capsys)
    assert "names 'summary' twice" in err and "analyses" in err, err
    assert not out.exists()


def test_analyse_archive_refuses_a_repeated_analysis(small_log, tmp_path):
    pytest.importorskip("distributed")
    from modalinfo.batch import analyse_archive

    with pytest.raises(ValueError, match=r"`analyses` names 'ordering' twice"):
        analyse_archive(small_log, ["ordering", "summary", "ordering"], tmp_path / "o")
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------ one glitched frame
def _ranks(out: str, n: int = 10) -> list[str]:
    rows = [ln.split() for ln in out.splitlines()]
    return [r[1] for r in rows if r and r[0].lstrip("~").isdigit()
            and int(r[0].lstrip("~")) <= n]


def test_one_glitched_frame_changes_no_rank_of_reorder_and_is_reported(tmp_path, capsys):
    """Issue 27, Must show: one frame of 4000 with Z2 at 100 sigma, the DEFAULT policy
    (warn): the first 10 ranks of ``modalinfo reorder`` are those of the clean log (same
    seed and budget, so the same samples) and the glitch is named on stderr. Run at the
    default budget and pupil without the bootstrap (~5 s each); at a quarter of the
    budget, ranks 6 and 7 (gains 0.039 and 0.040 nats, within the bootstrap interval of
    each other) can swap on sampling noise alone."""
    log = load(DATA / "kaos_like_closed_loop.npz")[:4000]
    y = np.array(log.coeffs)
    y[2000, 0] += 100 * y[:, 0].std()
    clean = save(log, tmp_path / "clean.npz")
    glitch = save(ModalLog(y, rate=log.rate, modes=log.modes, units=log.units,
                           wavelength=log.wavelength), tmp_path / "glitch.npz")
    assert exit_code(["reorder", clean, "--resamples", "0"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    first = _ranks(captured.out)
    assert exit_code(["reorder", glitch, "--resamples", "0"]) == 0
    captured = capsys.readouterr()
    assert len(first) == 10 and _ranks(captured.out) == first
    err = captured.err.splitlines()
    assert len(err) == 1 and "warning: " in err[0], err
    assert ("1 of 4000 frames flagged: 1 outlier value(s) in 1 frame(s) (frames 2000; "
            "most: Z2 1)") in err[0]


# ------------------------------------------------------------ bad values read from a file
@pytest.mark.parametrize("key, value, said", [
    ("rate", -2000.0, "the file's rate must be > 0.0; got -2000.0"),
    ("rate", float("nan"), "the file's rate must be finite; got nan"),
    ("wavelength", -5e-7, "the file's wavelength must be > 0.0; got -5e-07"),
])
def test_a_bad_value_stored_in_the_file_is_not_blamed_on_an_option(small_log, tmp_path,
                                                                   capsys, key, value, said):
    # Before: "'f.npz': --rate must be > 0.0; got -2000.0" to a user who typed no --rate.
    import json

    with np.load(small_log) as z:
        header = json.loads(str(z["header"]))
        coeffs = z["coefficients"]
    header[key] = value
    bad = tmp_path / "bad.npz"
    np.savez(bad, coefficients=coeffs, header=np.array(json.dumps(header)))
    assert exit_code(["info", bad]) == 2
    err = _one_line(capsys)
    assert said in err and "--" not in err.split("error: ", 1)[1], err


# ------------------------------------------------------------ bases that cannot be built
def test_kl_data_needs_as_many_frames_as_modes(tmp_path, capsys):
    # Before: a 2-frame log of 5 modes gave 3 arbitrary null-space "K-L modes" with
    # gains 0.0000 and a finite MI of numerical noise, exit 0.
    rng = np.random.default_rng(3)
    two = save(ModalLog(rng.standard_normal((2, 5)), rate=1e3, modes=[2, 3, 4, 5, 6],
                        units="rad"), tmp_path / "two.npz")
    assert exit_code(["reorder", two, "--basis", "kl-data", "--resamples", "0",
                      "--pupil-pixels", "16", "--budget", "2000"]) == 2
    assert "needs at least 5 frames for 5 K-L modes; got 2" in _one_line(capsys)


def test_kl_from_data_refuses_modes_beyond_the_rank():
    # the rank of A.T A / T is at most T (T - 1 once centred): linear algebra
    from modalinfo.bases import KLBasis, Pupil, ZernikeBasis

    zb = ZernikeBasis(Pupil(16), [2, 3, 4, 5])
    a = np.random.default_rng(0).standard_normal((4, 4))
    assert KLBasis.from_data(zb, a).n_modes == 4
    with pytest.raises(ValueError, match=r"needs at least 5 frames for 4 K-L modes; got 4"):
        KLBasis.from_data(zb, a, center=True)
    assert KLBasis.from_data(zb, a, center=True, n_modes=3).n_modes == 3
    with pytest.raises(ValueError, match=r"rank <= 3"):
        KLBasis.from_data(zb, a[:3])


def test_kl_theory_outer_scale_below_the_pupil_is_refused(small_log, capsys):
    # Before: --outer-scale 1e-3 (1 mm) built a K-L of a pupil far beyond L0, exit 0.
    assert exit_code(["reorder", small_log, "--basis", "kl-theory", "--outer-scale", "0.5",
                      "--resamples", "0", "--pupil-pixels", "16", "--budget", "2000"]) == 2
    err = _one_line(capsys)
    assert ("--outer-scale must be > the pupil diameter (assumed: the log records none) = 1 m"
            in err), err


# ------------------------------------------------------------ estimator options
def test_ksg_k_at_or_beyond_the_sample_is_refused():
    # Before: k = 5000 on 2000 samples was clamped to 1999 in silence (MI 5e-7 for 0.35).
    from modalinfo.information import mutual_information

    rng = np.random.default_rng(0)
    x = rng.standard_normal(200)
    y = x + rng.standard_normal(200)
    for k in (200, 5000):
        with pytest.raises(ValueError, match=rf"`k` must be < the number of samples \(200\); "
                                             rf"got {k}"):
            mutual_information(x, y, method="ksg", k=k)
    from modalinfo.information import BiasRuleWarning

    with pytest.warns(BiasRuleWarning, match="neighbour ball"):  # since audit 9
        assert np.isfinite(mutual_information(x, y, method="ksg", k=199))


# ------------------------------------------------------------ Ctrl-C at any moment
def test_ctrl_c_while_the_parser_is_built_is_one_line_and_130(monkeypatch, capsys):
    # Before: a KeyboardInterrupt while the subcommands were imported (seconds on a busy
    # machine) printed Python's traceback.
    import modalinfo.cli as cli

    def interrupted():
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", interrupted)
    assert cli.main(["info", "x.npz"]) == 130
    assert capsys.readouterr().err == "modalinfo: interrupted\n"


# ------------------------------------------------------------ more entries checked first
def test_an_output_folder_that_takes_no_file_is_refused_before_work(small_log, capsys):
    # Before: `--plot /proc/f.png` computed every curve, then failed naming a temporary
    # file ('/proc/.f.png.xxxx.tmp'); /proc takes no new file, even for root.
    assert exit_code(["convert", small_log, "/proc/x.npz", "--quiet"]) == 2
    assert "OUT '/proc/x.npz': cannot write in '/proc'" in _one_line(capsys)


def test_select_extra_on_another_clock_is_refused(small_log, tmp_path, capsys):
    # Before: the same number of frames at 1000 Hz against LOG's 2000 Hz ran (exit 0).
    rng = np.random.default_rng(4)
    extra = save(ModalLog(rng.standard_normal((300, 2)), rate=1000.0, modes=[5, 6],
                          units="rad"), tmp_path / "extra.npz")
    assert exit_code(["select", small_log, "--target", "Z2", "--extra", extra,
                      "--max-lag", "2", "--surrogates", "19", "--no-intervals"]) == 2
    assert "--extra is sampled at 1000 Hz, LOG at 2000 Hz" in _one_line(capsys)


def test_a_zernike_finer_than_the_pupil_grid_is_refused(tmp_path, capsys):
    # Before: Z5000 (radial order 99) on a 16-pixel pupil was scored (0.19 nats).
    rng = np.random.default_rng(5)
    log = save(ModalLog(rng.standard_normal((200, 3)), rate=1e3, modes=[2, 3, 5000],
                        units="rad"), tmp_path / "z.npz")
    assert exit_code(["reorder", log, "--pupil-pixels", "16", "--resamples", "0",
                      "--budget", "2000"]) == 2
    assert "--pupil-pixels must be >= 198 to sample Z5000 (radial order 99" in _one_line(
        capsys)


def test_batch_task_verifies_the_checksum_memory_mapping_skipped(small_log, tmp_path):
    # Before: a CRC-damaged NPZ (one byte of its data flipped) got an "ok" summary row.
    from modalinfo.batch.analyses import resolve_params, run_log_task
    from modalinfo.io.files import LogFormatError

    data = bytearray(small_log.read_bytes())
    data[len(data) // 2] ^= 0xFF
    bad = tmp_path / "bad.npz"
    bad.write_bytes(bytes(data))
    task = {"fmt": None, "hints": {}, "analysis": "summary",
            "params": resolve_params("summary")}
    assert run_log_task({**task, "path": str(small_log)})["n_frames"] == 300
    with pytest.raises(LogFormatError, match="do not match their CRC-32 checksum"):
        run_log_task({**task, "path": str(bad)})


def test_paper_figures_only_naming_a_figure_twice_is_refused(tmp_path, capsys):
    # Before: `--only 1,1` made Figure 1 once (exit 0): merged without a word.
    from paper_figures.__main__ import main as figures

    try:
        code = figures(["--only", "1,1", "--out", str(tmp_path / "f")])
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    assert "--only names figure 1 twice" in _one_line(capsys)
    assert not (tmp_path / "f").exists()


def test_select_on_values_whose_squares_overflow_is_refused_by_name(tmp_path, capsys):
    # Before: "zero-size array to reduction operation maximum which has no identity" (a
    # numpy message from inside the search) for a log of 1e300 values.
    rng = np.random.default_rng(6)
    huge = save(ModalLog(rng.standard_normal((300, 3)) * 1e300, rate=1e3, modes=[2, 3, 4],
                         units="rad"), tmp_path / "huge.npz")
    assert exit_code(["select", huge, "--target", "Z2", "--max-lag", "2", "--surrogates",
                      "19", "--no-intervals"]) == 2
    assert "where its sums of squares overflow float64" in _one_line(capsys)
