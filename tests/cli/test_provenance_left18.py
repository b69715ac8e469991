"""Outputs record what made them: the package version, the command line, the input's hash.

Reference: ``hashlib.sha256`` of the input file's bytes and ``os.stat`` of its size,
computed here, outside the code; the command line as the test typed it; and
``modalinfo.__version__``. Re-running a command (same command line, another working
folder) gives byte-identical files, a tampered input a different recorded hash, and
files written before the record existed still read (the key removed from a new one).
Adversarial round 18 PART b, rows P01-P06 (forecast.json, reorder's JSON and converted
logs recorded their settings but not the code, the command nor the input).
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

import modalinfo
from modalinfo.io import load, save
from modalinfo.ordering.result import OrderingResult
from modalinfo.telemetry import ModalLog

from .conftest import exit_code, write_small_log


def _fingerprint(path) -> dict:
    data = path.read_bytes()
    return {"sha256": hashlib.sha256(data).hexdigest(), "bytes": len(data)}


def _check_record(record: dict, argv: list[str], source) -> None:
    assert record["command"] == ["modalinfo", *argv]
    assert record["input"] == _fingerprint(source)
    assert record["modalinfo"].startswith(modalinfo.__version__ + "+src.")


def test_forecast_json_records_and_reruns_byte_identical(tmp_path, monkeypatch):
    for where in ("a", "b"):
        (tmp_path / where).mkdir()
        write_small_log(tmp_path / where / "log.npz", 400)
    argv = ["forecast", "log.npz", "--horizon", "2", "--predictors", "linear", "--out", "f",
            "--quiet"]
    texts = []
    for where in ("a", "b"):
        monkeypatch.chdir(tmp_path / where)
        assert exit_code(argv) == 0
        texts.append((tmp_path / where / "f" / "forecast.json").read_bytes())
    assert texts[0] == texts[1]  # no time of day, no absolute path
    record = json.loads(texts[0])["provenance"]
    _check_record(record, argv, tmp_path / "a" / "log.npz")
    assert record["seed"] is None  # forecast takes no seed
    # a tampered input (one coefficient x 1.5) is told apart by its hash
    log = tmp_path / "a" / "log.npz"
    original = load(log)
    coeffs = np.array(original.coeffs)
    coeffs[10, 1] *= 1.5
    log.unlink()
    save(ModalLog(coeffs, rate=original.rate, modes=original.modes, units=original.units), log)
    monkeypatch.chdir(tmp_path / "a")
    assert exit_code([*argv[:-3], "--out", "g", "--quiet"]) == 0
    again = json.loads((tmp_path / "a" / "g" / "forecast.json").read_text())["provenance"]
    assert again["input"]["sha256"] == _fingerprint(log)["sha256"] != record["input"]["sha256"]


def test_reorder_json_records_and_old_files_read(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_small_log(tmp_path / "log.npz", 300)
    argv = ["reorder", "log.npz", "--method", "mi_marginal", "--seed", "7", "--budget", "2000",
            "--out", "o.json"]
    assert exit_code(argv) == 0
    data = json.loads((tmp_path / "o.json").read_text())
    _check_record(data["provenance"], argv, tmp_path / "log.npz")
    assert data["provenance"]["seed"] == 7
    new = OrderingResult.from_json(tmp_path / "o.json")
    del data["provenance"]  # a file written before the record existed
    (tmp_path / "old.json").write_text(json.dumps(data))
    old = OrderingResult.from_json(tmp_path / "old.json")
    assert np.array_equal(old.order, new.order) and old.labels == new.labels


def test_convert_chain_names_each_source(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    write_small_log(tmp_path / "log.npz", 50)
    first = ["convert", "log.npz", "a.h5"]
    second = ["convert", "a.h5", "b.fits"]
    third = ["convert", "b.fits", "c.npz"]
    for argv in (first, second, third):
        assert exit_code([*argv, "--quiet"]) == 0
    original = load(tmp_path / "log.npz")
    final = load(tmp_path / "c.npz")
    # the data unchanged, bitwise
    assert final.coeffs.dtype == original.coeffs.dtype
    assert np.array_equal(final.coeffs.view(np.uint8), original.coeffs.view(np.uint8))
    assert (final.modes, final.rate, final.units) == (original.modes, original.rate,
                                                      original.units)
    assert {k: v for k, v in final.metadata.items() if k != "provenance"} == original.metadata
    steps = final.metadata["provenance"]
    assert len(steps) == 3
    for step, argv, source in zip(steps, (first, second, third), ("log.npz", "a.h5", "b.fits"),
                                  strict=True):
        _check_record(step, [*argv, "--quiet"], tmp_path / source)
    assert "provenance" not in original.metadata  # a log without the record reads
    # re-running a conversion (same command line, another folder) gives the same bytes
    for where in ("x", "y"):
        (tmp_path / where).mkdir()
        (tmp_path / where / "log.npz").write_bytes((tmp_path / "log.npz").read_bytes())
        monkeypatch.chdir(tmp_path / where)
        for ext in ("npz", "csv", "fits", "h5"):
            assert exit_code(["convert", "log.npz", f"o.{ext}", "--quiet"]) == 0
    for ext in ("npz", "csv", "fits", "h5"):
        assert (tmp_path / "x" / f"o.{ext}").read_bytes() == \
            (tmp_path / "y" / f"o.{ext}").read_bytes()
