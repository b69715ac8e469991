"""Parts of ``modalinfo batch`` that need no cluster: inputs, keys, row store, CLI errors.

References: ``glob`` / ``os.walk`` listings and hand-written manifests (expected
entries spelled out), ``hashlib.sha256`` of a canonical JSON written by hand,
``json`` reading of the row files, ``modalinfo.io.load`` with the same hints as the
manifest row (the manifest must give exactly what a direct call gives).
"""

from __future__ import annotations

import hashlib
import json
import os

import numpy as np
import pytest

from modalinfo.batch import engine
from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.batch.manifest import LogEntry, collect_logs, read_manifest
from modalinfo.common.tasks.threads import _limited_call


def test_directory_glob_and_manifest(tmp_path, helpers):
    root = tmp_path / "arch"
    (root / "day2").mkdir(parents=True)
    helpers.write_archive(root, n_good=3, corrupt=False)
    helpers.write_archive(root / "day2", n_good=2, corrupt=False)
    (root / "notes.md").write_text("not a log")
    (root / ".hidden.npz").write_bytes(b"")
    out = root / "out"
    (out / "rows").mkdir(parents=True)
    (out / "batch.csv").write_text("a,b\n1,2\n")
    found = collect_logs(root, exclude=[out])
    expected = sorted(["log000.npz", "log001.csv", "log002.fits", "day2/log000.npz",
                       "day2/log001.csv"])
    assert sorted(os.path.relpath(e.path, root) for e in found) == expected
    pattern = str(root / "**" / "*.npz")
    assert [e.path for e in collect_logs(pattern)] == [
        str(p.resolve()) for p in sorted(root.glob("**/*.npz")) if not p.name.startswith(".")]
    manifest = tmp_path / "m.csv"
    manifest.write_text("# archive of a foreign AO system\npath,fmt,rate,in_modes,in_units\n"
                        "arch/log000.npz,,,,\narch/raw.npy,npy,1000,2-4,nm\n")
    entries = read_manifest(manifest)
    assert entries == [
        LogEntry(str((root / "log000.npz").resolve()), None, {}),
        LogEntry(str((root / "raw.npy").resolve()), "npy",
                 {"rate": 1000.0, "modes": [2, 3, 4], "units": "nm"}),
    ]
    # a manifest is recognised among inputs; the same file twice is listed once
    both = collect_logs([manifest, root / "log000.npz"], fmt=None, hints={"nonfinite": "drop"})
    assert [e.path for e in both] == [entries[0].path, entries[1].path]
    assert both[1].hints == {"nonfinite": "drop", "rate": 1000.0, "modes": [2, 3, 4],
                             "units": "nm"}
    # a log CSV is a log, not a manifest
    assert collect_logs(root / "log001.csv")[0].path == str((root / "log001.csv").resolve())


def test_manifest_hints_give_what_load_gives(tmp_path):
    from modalinfo.io import load

    x = np.random.default_rng(3).normal(size=(64, 3))
    np.save(tmp_path / "raw.npy", x)
    manifest = tmp_path / "m.csv"
    manifest.write_text("path,rate,in_modes,in_units,wavelength\nraw.npy,400,4-6,nm,6e-7\n")
    (entry,) = read_manifest(manifest)
    payload = {"path": entry.path, "fmt": entry.fmt, "hints": entry.hints,
               "analysis": "summary", "params": resolve_params("summary")}
    row = run_log_task(payload)
    direct = load(tmp_path / "raw.npy", rate=400.0, modes=[4, 5, 6], units="nm",
                  wavelength=6e-7)
    assert row["rate"] == direct.rate == 400.0
    assert row["units"] == "nm" and row["n_modes"] == 3
    np.testing.assert_allclose(row["rms_total"], np.sqrt(np.sum(np.mean(x * x, axis=0))),
                               rtol=1e-12)


@pytest.mark.parametrize("text", [
    "\ufeffpath,rate,in_units\nraw.npy,400,nm\n",  # a spreadsheet's byte-order mark
    "path;rate;in_units\r\nraw.npy;400;nm\r\n",  # a decimal-comma locale's export
    "path\trate\tin_units\nraw.npy\t400\tnm\n",
])
def test_spreadsheet_manifests_give_the_hand_written_entry(tmp_path, text):
    # audit 9-files: a BOM was refused as 'no path column'; ';' made the manifest a log
    np.save(tmp_path / "raw.npy", np.zeros((8, 2)))
    manifest = tmp_path / "m.csv"
    manifest.write_bytes(text.encode("utf-8"))
    expected = [LogEntry(str((tmp_path / "raw.npy").resolve()), None,
                         {"rate": 400.0, "units": "nm"})]
    assert collect_logs([manifest]) == expected


@pytest.mark.parametrize("text, message", [
    ("path,colour\na.npz,red\n", "unknown column 'colour'"),
    ("path,rate\na.npz,fast\n", "row 2: column 'rate' must be a number"),
    ("path,rate\n,100\n", "row 2: empty path"),
])
def test_manifest_errors_name_the_row(tmp_path, text, message):
    manifest = tmp_path / "m.csv"
    manifest.write_text(text)
    with pytest.raises(ValueError, match=message):
        read_manifest(manifest)


def test_missing_inputs_raise(tmp_path):
    with pytest.raises(ValueError, match="matches no file"):
        collect_logs(str(tmp_path / "*.npz"))
    with pytest.raises(ValueError, match="neither a file"):
        collect_logs(tmp_path / "absent.npz")
    with pytest.raises(ValueError, match="no log files"):
        collect_logs(tmp_path)


def test_task_key_is_sha256_of_canonical_json():
    key = engine.task_key("abc", "summary", {"b": 1, "a": [1.5, None]})
    text = '["' + engine.package_version() + '","abc","summary",{"a":[1.5,null],"b":1}]'
    assert key == hashlib.sha256(text.encode()).hexdigest()
    assert engine.task_key("abc", "summary", {"a": [1.5, None], "b": 1}) == key
    assert engine.task_key("abc", "summary", {"a": [1.5, None], "b": 2}) != key
    assert engine.task_key("abd", "summary", {"a": [1.5, None], "b": 1}) != key


def test_row_store_is_one_atomic_file_per_key(tmp_path):
    store = engine.RowStore(tmp_path / "out")
    store.write("k1", {"status": "ok", "x": 0.1 + 0.2})
    store.write("k2", {"status": "error", "error_type": "ValueError"})
    store.write("k3", {"status": "lost", "error_type": "KilledWorker"})
    (store.rows_dir / ".k4.json.abc.tmp").write_text("{half a row")  # a crashed write
    assert sorted(p.name for p in store.rows_dir.glob("*.json")) == [
        "k1.json", "k2.json", "k3.json"]
    with open(store.rows_dir / "k1.json") as fh:
        assert json.load(fh) == {"status": "ok", "x": 0.30000000000000004, "key": "k1"}
    assert store.finished() == {"k1", "k2"}  # a lost task is run again
    assert store.finished(retry_errors=True) == {"k1"}
    store.write("k1", {"status": "ok", "x": 1.0})
    assert [r["x"] for r in store.rows() if r["key"] == "k1"] == [1.0]
    with pytest.raises(ValueError, match="plain file name"):
        store.write("../escape", {})


def test_run_tasks_with_nothing_to_do_starts_no_cluster(tmp_path):
    store = engine.RowStore(tmp_path)
    spec = engine.TaskSpec("k1", {}, {})
    store.write("k1", {"status": "ok"})

    def no_client():
        raise AssertionError("a cluster was asked for")

    report = engine.run_tasks([spec, spec], run_log_task, store, no_client, progress=False)
    assert (report.n_specs, report.n_skipped, report.n_submitted) == (1, 1, 0)


def test_thread_budget_never_oversubscribes():
    for cpus in (1, 2, 8, 64):
        for workers in (1, 2, 3, 8):
            for per in (1, 2, 4):
                t = engine.task_threads(workers, per, cpus)
                assert t >= 1
                assert workers * per * t <= max(cpus, workers * per)
    # numba is limited per task (numba.set_num_threads), never through the worker's env
    assert engine.thread_env(3) == {"OMP_NUM_THREADS": "3", "OPENBLAS_NUM_THREADS": "3",
                                    "MKL_NUM_THREADS": "3"}


def test_errors_inside_a_task_become_rows():
    row = _limited_call(run_log_task, {"path": "/nonexistent/x.npz", "fmt": None,
                                              "hints": {}, "analysis": "summary",
                                              "params": {"chunk_frames": 10}}, 1)
    assert row["status"] == "error" and row["error_type"] == "FileNotFoundError"
    assert "/nonexistent/x.npz" in row["error_message"]


def test_missing_extra_is_named():
    from modalinfo.common.deps import require

    with pytest.raises(ImportError, match=r"pip install 'modalinfo\[dist\]'"):
        require("modalinfo_no_such_module")


@pytest.mark.parametrize("argv, message", [
    (["--analyses", "summary,colour"], "`analyses` must be among"),
    (["--set", "forecast.horizon"], "--set must look like analysis.name=value"),
    (["--set", "forecast.colour=1", "--analyses", "forecast"], "unknown parameter"),
    (["--set", "ordering.budget=10"], "not among the analyses run"),
    (["--workers", "0"], "--workers must be >= 1"),
])
def test_cli_input_errors_are_one_line_exit_2(tmp_path, capsys, helpers, argv, message):
    from modalinfo.cli import main

    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    code = main(["batch", str(tmp_path), "--out", str(tmp_path / "out"), *argv])
    err = capsys.readouterr().err
    assert code == 2 and message in err and err.count("\n") == 1
    assert not (tmp_path / "out").exists()  # nothing started, nothing written


def test_cli_refuses_a_foreign_output_directory(tmp_path, capsys, helpers):
    from modalinfo.cli import main

    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    other = tmp_path / "results"
    other.mkdir()
    (other / "thesis.tex").write_text("mine")
    assert main(["batch", str(tmp_path), "--out", str(other)]) == 2
    assert "holds no earlier batch" in capsys.readouterr().err
    assert sorted(p.name for p in other.iterdir()) == ["thesis.tex"]


def test_time_windows_cover_the_log_without_short_tails():
    from modalinfo.batch.archive import time_windows

    assert time_windows(256, 100) == [(0, 100), (100, 256)]
    assert time_windows(300, 100) == [(0, 100), (100, 200), (200, 300)]
    assert time_windows(50, 100) == [(0, 50)]
    for n, w in ((1000, 7), (999, 1000), (12345, 100)):
        win = time_windows(n, w)
        assert win[0][0] == 0 and win[-1][1] == n
        assert all(a[1] == b[0] for a, b in zip(win, win[1:], strict=False))
        assert all(w <= b - a < 2 * w for a, b in win) or len(win) == 1


def test_modes_parameter_restricts_the_analysed_modes(tmp_path, helpers):
    """A 1000-mode system orders a subset: the row names exactly the modes asked for."""
    from modalinfo.io import save

    save(helpers.make_log(0, n_modes=8), tmp_path / "a.npz")  # Z2..Z9
    base = {"path": str(tmp_path / "a.npz"), "fmt": None, "hints": {}}
    row = run_log_task({**base, "analysis": "ordering", "params": resolve_params(
        "ordering", {"modes": "3-6", "budget": 2000, "pupil_pixels": 16, "windows": 0})})
    assert row["n_modes"] == 8 and row["modes_analysed"] == 4
    assert sorted(row["order"].split()) == ["Z3", "Z4", "Z5", "Z6"]
    row = run_log_task({**base, "analysis": "forecast", "params": resolve_params(
        "forecast", {"modes": [2, 9], "predictors": "linear"})})
    assert row["modes_analysed"] == 2


def test_forecast_horizon_beyond_the_log_is_an_error_row_at_once(tmp_path, helpers):
    from modalinfo.batch.analyses import _forecast

    params = resolve_params("forecast", {"horizon": 100_000_000, "predictors": "linear"})
    with pytest.raises(ValueError, match="below the log's 256 frames"):
        _forecast(helpers.make_log(0), params)


def test_an_earlier_batch_output_inside_the_inputs_is_not_read(tmp_path, helpers):
    from modalinfo.io import save

    save(helpers.make_log(0), tmp_path / "a.npz")
    old = tmp_path / "old_out"
    (old / "rows").mkdir(parents=True)
    (old / "hashes.json").write_text("{}")
    (old / "batch.csv").write_text('"path","analysis"\n')
    names = [os.path.basename(e.path) for e in collect_logs(tmp_path)]
    assert names == ["a.npz"]
