"""Adversarial round 12, PART b (command lines, files, environment): the fixed rows.

References, all outside the code under test: pandas' ``read_csv`` (an empty cell is a
missing value, NaN) and ``numpy.interp`` (the value a linear interpolation gives);
the gzip format's magic bytes (``1f 8b``, RFC 1952) written by Python's :mod:`gzip`;
the strict JSON / CSV reading of ``forecast``'s outputs by :mod:`json` and pandas
(one spelling of a missing value); the paths of the files each test writes; the
kernel's address-space limit (``setrlimit(RLIMIT_AS)``). Rows of docs/ADVERSARIAL.md
"Round 12 PART b". Each test fails on the code before its fix.
"""

from __future__ import annotations

import errno
import gzip
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from modalinfo.batch.manifest import collect_logs
from modalinfo.io import load

from .conftest import exit_code, write_small_log

ROOT = Path(__file__).resolve().parents[2]


def _pandas_csv(tmp_path: Path, blank: tuple[int, str] | None, frames: int = 200) -> Path:
    """A log exported by pandas (time column, Z2..Z6), one cell left empty (NaN)."""
    rng = np.random.default_rng(0)
    frame = pd.DataFrame(rng.standard_normal((frames, 5)), columns=[f"Z{j}" for j in
                                                                    range(2, 7)])
    frame.insert(0, "time", np.arange(frames) / 1000.0)
    if blank is not None:
        frame.loc[blank[0], blank[1]] = np.nan
    path = tmp_path / "pandas.csv"
    frame.to_csv(path, index=False)  # NaN written as an empty cell
    return path


# ------------------------------------------- A07/A08: an empty CSV cell is a missing value
def test_empty_cell_is_nan_for_the_nonfinite_policy(tmp_path, capsys):
    path = _pandas_csv(tmp_path, (50, "Z4"))
    assert exit_code(["info", path]) == 2
    err = capsys.readouterr().err
    assert "corrupt" not in err and "--nonfinite" in err
    reference = pd.read_csv(path)  # pandas: the empty cell is NaN, the rest numbers
    log = load(path, nonfinite="interpolate")
    z4 = reference["Z4"].to_numpy()
    good = np.isfinite(z4)
    expected = np.interp(50, np.flatnonzero(good), z4[good])
    assert log.coeffs[50, 2] == pytest.approx(expected, rel=1e-12)
    np.testing.assert_array_equal(log.coeffs[good, 2], z4[good])


def test_all_empty_column_is_named(tmp_path, capsys):
    frames = 200
    path = _pandas_csv(tmp_path, None, frames)
    frame = pd.read_csv(path)
    frame["Z3"] = np.nan
    frame.to_csv(path, index=False)
    assert exit_code(["info", path, "--nonfinite", "interpolate"]) == 2
    err = capsys.readouterr().err
    assert "corrupt" not in err and "no finite value" in err


# ---------------------------------------------- A11-A13: gzip-compressed logs are named
@pytest.mark.parametrize("name", ["log.csv.gz", "log.fits.gz", "log.npz.gz"])
def test_gzip_is_named_with_the_remedy(tmp_path, capsys, name):
    source = write_small_log(tmp_path / "x.npz", 50)
    path = tmp_path / name
    with gzip.open(path, "wb") as fh:
        fh.write(source.read_bytes())
    assert path.read_bytes()[:2] == b"\x1f\x8b"  # RFC 1952 magic
    assert exit_code(["info", path]) == 2
    err = capsys.readouterr().err
    assert "gzip-compressed" in err and "gunzip" in err and "UTF-8" not in err


# ------------------------------------ B06/B11: a log named inside the output directory
def test_named_log_inside_the_output_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    inside = write_small_log(out / "extra.npz", 50)
    outside = write_small_log(tmp_path / "c.npz", 50)
    with pytest.raises(ValueError, match="inside the output directory"):
        collect_logs([str(inside), str(outside)], exclude=[out])
    # a manifest naming it too
    manifest = tmp_path / "m.csv"
    manifest.write_text(f"path\n{inside}\n{outside}\n")
    with pytest.raises(ValueError, match="inside the output directory"):
        collect_logs([str(manifest)], exclude=[out])
    # a folder walked is still searched without the output directory in it
    manifest.unlink()
    entries = collect_logs([str(tmp_path)], exclude=[out])
    assert [Path(e.path).name for e in entries] == ["c.npz"]


# --------------------------------------------------------- O02: forecast.csv's missing cells
def test_forecast_csv_spells_missing_one_way(tmp_path):
    log = write_small_log(tmp_path / "x.npz", 400)
    out = tmp_path / "f"
    assert exit_code(["forecast", log, "--predictors", "linear", "--horizon", "1",
                      "--quiet", "--out", out]) == 0
    text = (out / "forecast.csv").read_text()
    assert "nan" not in text.lower()
    table = pd.read_csv(out / "forecast.csv")
    with open(out / "forecast.json") as fh:  # strict JSON: no NaN tokens
        json.load(fh, parse_constant=lambda c: pytest.fail(f"JSON token {c}"))
    whole = table[table["mode"] == "wavefront"].set_index("predictor")
    # persistence is the baseline: no Diebold-Mariano test against itself
    assert np.isnan(whole.loc["persistence", "p_value"])
    assert np.isfinite(whole.loc["linear", "p_value"])


# ------------------------------------------- E07: out of memory while loading the program
def test_memory_refusal_reads_the_chain(capsys):
    from modalinfo.common.startup import memory_refusal

    try:
        try:
            raise OSError("libllvmlite.so: failed to map segment from shared object")
        except OSError:
            raise OSError("Could not find/load shared object file 'libllvmlite.so'") from None
    except OSError as exc:
        chained = exc
    chained.__context__ = OSError("libllvmlite.so: failed to map segment from shared object")
    assert memory_refusal("modalinfo", chained) == 2
    assert capsys.readouterr().err.count("\n") == 1
    assert memory_refusal("modalinfo", OSError(errno.ENOMEM, "Cannot allocate memory")) == 2
    with pytest.raises(OSError, match="disk"):
        memory_refusal("modalinfo", OSError(errno.EIO, "disk"))


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS semantics")
@pytest.mark.parametrize("module", ["modalinfo", "paper_figures", "closedloop"])
def test_address_space_limit_is_one_line(tmp_path, module):
    import resource

    def limit():  # below what numba's LLVM needs to map; NumPy itself loads
        resource.setrlimit(resource.RLIMIT_AS, (300 * 2**20, 300 * 2**20))

    argv = {"modalinfo": ["info", "x.npz"], "paper_figures": ["--only", "1", "--out", "o"],
            "closedloop": ["run", "--preset", "table1"]}[module]
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, "-m", module, *argv], cwd=tmp_path, env=env,
                          preexec_fn=limit, capture_output=True, text=True, timeout=120)
    if done.returncode == 0:
        pytest.skip("the program loaded within 300 MiB of address space here")
    assert "Traceback" not in done.stderr
    assert done.returncode == 2
    assert "out of memory" in done.stderr and done.stderr.count("\n") == 1


# ----------------------------------------- H22: a one-frame --stability window, before work
def test_one_frame_stability_window_refused_before_work(tmp_path, capsys):
    log = write_small_log(tmp_path / "x.npz", 40)
    assert exit_code(["reorder", log, "--stability", "1", "--resamples", "0",
                      "--quiet"]) == 2
    out, err = capsys.readouterr()
    assert out == ""  # nothing ordered first
    assert "--stability must be a window of 2..20" in err and err.count("\n") == 1
