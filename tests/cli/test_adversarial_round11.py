"""Adversarial round 11, PART b (command lines, files, environment): the fixed rows.

References, all outside the code under test: the timestamps each test writes with
astropy (a ``TIME`` column of 0.5 ms steps stated ``TUNIT = 'ms'`` is a 2 kHz log, the
FITS standard's unit keyword); ``pathlib.Path("") == Path(".")`` (an empty ``--out`` is
the current folder); the grid each test writes (two overrides setting one key to one
value are one config); the HDF5 links each test makes with h5py; Parquet's magic bytes
``PAR1`` (Apache Parquet format specification); the shipped logs' provenance in
data/README.md (closed-loop residuals); rows of docs/ADVERSARIAL.md "Round 11 PART b".
Each test fails on the code before its fix.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code, write_small_log


# ------------------------------------------------- F04: a FITS TIME column in ms (TUNIT)
def test_a_fits_time_column_follows_its_tunit(tmp_path):
    from astropy.io import fits

    rng = np.random.default_rng(4)
    coeffs = rng.standard_normal((400, 3))
    t_ms = np.arange(400) * 0.5  # 2 kHz, stated in ms by TUNIT only
    cols = [fits.Column(name="TIME", format="D", unit="ms", array=t_ms)]
    cols += [fits.Column(name=f"Z{j + 2}", format="D", unit="rad", array=coeffs[:, j])
             for j in range(3)]
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(cols)]).writeto(
        tmp_path / "ms.fits")
    log = load(tmp_path / "ms.fits")
    assert log.rate == pytest.approx(2000.0, rel=1e-9)  # 2 Hz before the fix
    assert np.allclose(log.timestamps, t_ms / 1000.0, rtol=0, atol=1e-15)
    # a TIME column stated in seconds is read as before
    cols[0] = fits.Column(name="TIME", format="D", unit="s", array=t_ms / 1000.0)
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU.from_columns(cols)]).writeto(
        tmp_path / "s.fits")
    assert load(tmp_path / "s.fits").rate == pytest.approx(2000.0, rel=1e-9)


# ---------------------------------------------- E09, R38: --out "" is not the current folder
def test_an_empty_output_folder_name_is_refused(tmp_path, capsys, monkeypatch):
    from closedloop.cli import main as closedloop_main

    log = write_small_log(tmp_path / "log.npz", 400)
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)  # an empty folder: the empty name wrote here before
    assert exit_code(["forecast", log, "--predictors", "linear", "--modes", "2",
                      "--horizon", "1", "--out", ""]) == 2
    assert exit_code(["batch", log, "--analyses", "summary", "--out", ""]) == 2
    (tmp_path / "g.toml").write_text('preset = "kaos"\nduration = 0.01\n')
    with pytest.raises(SystemExit) as exc:  # the parser's usage error: one line, exit 2
        closedloop_main(["sweep", str(tmp_path / "g.toml"), "--out", ""])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("must name a folder; got an empty name") == 3
    assert list(work.iterdir()) == []


# --------------------------------------- R36: two override names for one config
def test_sweep_refuses_two_overrides_giving_one_config():
    from closedloop.sweep import sweep_specs

    grid = {"preset": "kaos", "duration": 0.01,
            "overrides": [{"name": "a", "loop.gain": 0.3}, {"name": "b", "loop.gain": 0.3}]}
    with pytest.raises(ValueError, match="'a' and 'b' give the same config"):
        sweep_specs(grid)  # 'b' vanished from the table before (one key, one row)
    grid["overrides"][1]["loop.gain"] = 0.31
    assert {s.labels["override"] for s in sweep_specs(grid)} == {"a", "b"}


# ------------------------------------------ R28: Figure 1's text on a --log
def test_figure1_text_calls_a_user_log_by_its_name():
    from paper_figures.__main__ import DEFAULT_LOG, SIMULATED_LOG
    from paper_figures.fig1_fitting_error import _described

    assert _described("`pol.fits`") == "the log `pol.fits`"  # not "our closed-loop residual"
    for shipped in (DEFAULT_LOG, SIMULATED_LOG):  # the shipped residuals keep their words
        assert _described(f"`{shipped}`") == "our closed-loop residual"


# ----------------------------------------------------- V08: a constant --target
@pytest.mark.parametrize("value", [0.0, 0.1])
def test_select_refuses_a_constant_target(tmp_path, capsys, value):
    coeffs = np.random.default_rng(2).standard_normal((400, 3))
    coeffs[:, 0] = value  # tip removed (0) or a stuck mode (0.1)
    path = save(ModalLog(coeffs, rate=1000.0, units="rad"), tmp_path / "c.npz")
    code = exit_code(["select", path, "--target", "Z2", "--max-lag", 2, "--no-intervals",
                      "--surrogates", 19])
    err = capsys.readouterr().err
    assert code == 2 and "--target Z2 is constant" in err and len(err.splitlines()) == 1
    assert exit_code(["select", path, "--target", "Z3", "--max-lag", 2, "--no-intervals",
                      "--surrogates", 19]) == 0


# ---------------------------------------------------- H05, H06: links named by --dataset
def test_hdf5_dataset_naming_a_link_says_so(tmp_path, capsys):
    import h5py

    data = np.random.default_rng(3).standard_normal((300, 3))
    with h5py.File(tmp_path / "target.h5", "w") as f:
        f["coeffs"] = data
    with h5py.File(tmp_path / "links.h5", "w") as f:
        f["real/coeffs"] = data
        f["alias"] = h5py.SoftLink("/real/coeffs")
        f["outside"] = h5py.ExternalLink("target.h5", "/coeffs")
    path = tmp_path / "links.h5"
    assert exit_code(["info", path, "--rate", 1000, "--dataset", "alias"]) == 2
    assert "it is a link to '/real/coeffs'" in capsys.readouterr().err
    assert exit_code(["info", path, "--rate", 1000, "--dataset", "outside"]) == 2
    assert "in another file, 'target.h5', not followed" in capsys.readouterr().err
    assert exit_code(["info", path, "--rate", 1000, "--dataset", "real/coeffs"]) == 0


# ----------------------------------------------------- R12: a result table fed as a log
def test_a_parquet_table_fed_as_a_log_is_named(tmp_path, capsys):
    path = tmp_path / "batch.parquet"
    path.write_bytes(b"PAR1" + bytes(range(128, 256)) + b"PAR1")
    assert exit_code(["info", path]) == 2
    err = capsys.readouterr().err
    assert "Apache Parquet" in err and "UTF-8" not in err


# ---------------------------------------- R39: one AOT file, two loops, in a manifest
def test_a_manifest_naming_one_file_for_two_loops_keeps_both(tmp_path):
    from modalinfo.batch.manifest import collect_logs

    log = write_small_log(tmp_path / "a.npz", 100)
    manifest = tmp_path / "m.csv"
    manifest.write_text(f"path,loop\n{log},dm0\n{log},dm0.pol\n{log},dm0\n")
    entries = collect_logs(manifest)
    # the dm0.pol row vanished before (keyed by path alone); the repeated dm0 row is one
    assert [e.hints for e in entries] == [{"loop": "dm0"}, {"loop": "dm0.pol"}]
    assert {e.path for e in entries} == {str(log.resolve())}
