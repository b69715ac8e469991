"""Five CLI items of the rounds 54-55 (fix56-c): ``reorder --quiet``, raw dumps, cut files.

References: the JSON ``modalinfo reorder --out`` writes, read back with ``json.load``
(the same ordering with or without ``--quiet``); ``--quiet``'s meaning is that of
``convert`` / ``synth`` / ``forecast`` (nothing on stdout on success); the files given
back as logs are written here with numpy (``ndarray.tofile``, ``numpy.save``) and
astropy (``HDUList.writeto``), cut with ``os.truncate`` at the HDU boundary astropy's
``fileinfo`` reports, so each refusal is judged against what the bytes are.
"""

import json

import numpy as np
import pytest

from modalinfo.cli import main

from .conftest import write_small_log


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    return write_small_log(tmp_path_factory.mktemp("q") / "s.npz", 300)


# --- 1. reorder --quiet ----------------------------------------------------------------

def test_reorder_quiet_prints_nothing_and_writes_the_same_ordering(small, tmp_path, capsys):
    loud, silent = tmp_path / "loud.json", tmp_path / "silent.json"
    assert main(["reorder", str(small), "--method", "variance", "--resamples", "0",
                 "--pupil-pixels", "16", "--out", str(loud)]) == 0
    shown = capsys.readouterr().out
    assert "ordering written" in shown  # the loud run prints (else the test tells nothing)
    assert main(["reorder", str(small), "--method", "variance", "--resamples", "0",
                 "--pupil-pixels", "16", "--out", str(silent), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == ""
    with open(loud, encoding="utf-8") as a, open(silent, encoding="utf-8") as b:
        first, second = json.load(a), json.load(b)
    assert first["labels"] == second["labels"] and first["scores"] == second["scores"]


def test_reorder_quiet_without_out_is_refused_before_the_work(small, capsys, monkeypatch):
    import modalinfo.ordering as ordering

    def no_work(*args, **kwargs):  # the refusal comes before the ordering
        raise AssertionError("order_modes ran")

    monkeypatch.setattr(ordering, "order_modes", no_work)
    assert main(["reorder", str(small), "--method", "variance", "--resamples", "0",
                 "--pupil-pixels", "16", "--quiet"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1
    assert "--quiet without --out" in captured.err and "--out FILE.json" in captured.err


def test_reorder_quiet_says_its_caution_on_stderr(small, tmp_path, capsys):
    # the caution on too few replicates is a warning about the numbers written: with the
    # table gone it goes to stderr, one line, not lost
    out = tmp_path / "r.json"
    assert main(["reorder", str(small), "--budget", "2000", "--resamples", "2",
                 "--pupil-pixels", "16", "--out", str(out), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.count("\n") == 1
    assert "caution: 2 replicates are too few for 95% bounds" in captured.err
    assert json.loads(out.read_text(encoding="utf-8"))["n_resamples"] == 2


def test_quiet_help_is_one_wording(capsys):
    # reorder's help said "no progress bar" while convert's / forecast's said nothing is
    # printed: one helper, one wording
    helps = {}
    for command in ("reorder", "forecast", "convert", "synth"):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        text = " ".join(capsys.readouterr().out.split())
        helps[command] = text
    for command, text in helps.items():
        assert "--quiet print nothing on success (and no progress bar)" in text, command


# --- 2. raw pixel dumps and frame cubes given as a log ---------------------------------

@pytest.mark.parametrize(("name", "dtype"), [("px.raw", np.uint16), ("px.bin", np.float32),
                                             ("px.dat", np.float32), ("fe.rgba", np.uint8)])
def test_headerless_dump_is_named_with_its_element_counts(tmp_path, capsys, name, dtype):
    path = tmp_path / name
    rng = np.random.default_rng(1)
    frames = (rng.random((6, 32, 32)) * 4000).astype(dtype)
    if name == "px.dat":
        frames[:] = 0  # a zero-filled dump decodes as UTF-8 NULs: read as a CSV before
    frames.tofile(path)
    size = path.stat().st_size
    assert size == frames.nbytes
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "headerless binary dump" in err and f"{size:,} bytes" in err
    if size % 4 == 0:  # the float32 count the user can match to frames x pixels
        assert f"{size // 4:,} float32" in err
    assert "numpy.fromfile" in err and "frames x modes" in err


def test_text_dat_is_still_a_csv(tmp_path, capsys):
    # the guard: a text .dat (columns of numbers) is a log, as before
    path = tmp_path / "cols.dat"
    coeffs = np.random.default_rng(2).standard_normal((50, 3))
    np.savetxt(path, coeffs, delimiter=",")
    assert main(["info", str(path), "--rate", "100"]) == 0
    assert "50 frames x 3 modes" in capsys.readouterr().out


def test_npy_frame_cube_is_named_as_images(tmp_path, capsys):
    path = tmp_path / "cube.npy"
    np.save(path, np.zeros((40, 16, 24), np.float32))
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "3-D float32 array of shape (40, 16, 24)" in err
    assert "cube of images (40 frames of 16 x 24 pixels" in err
    assert "single mode's series" not in err  # the advice of another mistake


def test_npz_of_a_frame_cube_is_named_as_images(tmp_path, capsys):
    path = tmp_path / "cube.npz"
    np.savez(path, frames=np.zeros((30, 8, 12), np.float64), exposure=np.ones(30))
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "'frames' is a 3-D float64 array of shape (30, 8, 12)" in err
    assert "cube of images (30 frames of 8 x 12 pixels" in err


# --- 3. FITS / AOT files cut between two HDUs -------------------------------------------

def _cut_before(path, index, out):
    """Copy ``path`` to ``out`` cut where HDU ``index`` starts (astropy's ``fileinfo``)."""
    import os
    import shutil

    from astropy.io import fits

    with fits.open(path) as hdul:
        start = hdul.fileinfo(index)["hdrLoc"]
        names = [h.name for h in hdul]
    shutil.copy(path, out)
    os.truncate(out, start)
    return start, names


def test_fits_with_fewer_extensions_than_nextend(tmp_path, capsys):
    from astropy.io import fits

    whole = tmp_path / "three.fits"
    primary = fits.PrimaryHDU()
    primary.header["NEXTEND"] = 3
    rng = np.random.default_rng(3)
    fits.HDUList([primary, *(fits.ImageHDU(rng.standard_normal((200, 4)), name=f"E{k}")
                             for k in range(3))]).writeto(whole)
    assert main(["info", str(whole), "--rate", "100"]) == 0  # whole: read as before
    capsys.readouterr()
    cut = tmp_path / "two.fits"
    start, _ = _cut_before(whole, 3, cut)
    assert main(["info", str(cut), "--rate", "100"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "incomplete FITS file" in err and "NEXTEND = 3" in err and "holds 2" in err
    assert f"ending at byte {start} right after HDU 2 (E1)" in err


def test_modalinfo_fits_cut_before_its_times(tmp_path, capsys):
    from modalinfo.io import save
    from modalinfo.telemetry import ModalLog

    rng = np.random.default_rng(4)
    times = np.cumsum(rng.uniform(0.9e-3, 1.1e-3, 300))  # non-uniform: a TIMES extension
    whole = save(ModalLog(rng.standard_normal((300, 3)), timestamps=times, modes=[2, 3, 4],
                          units="rad"), tmp_path / "t.fits")
    cut = tmp_path / "t_cut.fits"
    start, names = _cut_before(whole, 1, cut)
    assert names[1] == "TIMES"
    assert main(["info", str(cut)]) == 2
    err = capsys.readouterr().err
    assert "incomplete FITS file" in err and "TIMES" in err
    assert f"ends at byte {start}, right after HDU 0 (primary)" in err


@pytest.fixture(scope="module")
def aot_file(tmp_path_factory, small):
    pytest.importorskip("aotpy")
    out = tmp_path_factory.mktemp("aot") / "s_aot.fits"
    assert main(["convert", str(small), str(out), "--to-fmt", "aot", "--quiet"]) == 0
    return out


@pytest.mark.parametrize("table", ["AOT_DETECTORS", "AOT_WAVEFRONT_SENSORS_SHACK_HARTMANN",
                                   "LOOP MODAL_COEFFICIENTS"])
def test_aot_cut_between_hdus_is_named_incomplete(aot_file, tmp_path, capsys, table):
    from astropy.io import fits

    with fits.open(aot_file) as hdul:
        index = [h.name for h in hdul].index(table)
    cut = tmp_path / "cut.fits"
    start, names = _cut_before(aot_file, index, cut)
    assert main(["info", str(cut)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "incomplete AOT file" in err and repr(table) in err
    assert f"ends at byte {start}, right after HDU {index - 1} ({names[index - 1]})" in err
    assert "AOTVerificationException" not in err


def test_aot_cut_inside_an_hdu_keeps_its_message(aot_file, tmp_path, capsys):
    import os
    import shutil

    cut = tmp_path / "inside.fits"
    shutil.copy(aot_file, cut)
    os.truncate(cut, aot_file.stat().st_size - 5000)  # inside the data
    assert main(["info", str(cut)]) == 2
    assert "truncated AOT file" in capsys.readouterr().err
