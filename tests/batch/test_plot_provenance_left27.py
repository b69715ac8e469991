"""Batch's archive plots carry the run's record in their PNG metadata (left27-geometry).

docs/ADVERSARIAL.md, "Round 27 PART b, issue 27", Left (P20): forecast's PNGs gained
their record (P09) but batch's ``plots/archive_vs_*.png`` carried only Matplotlib's
``Software`` key, so a plot out of its folder named neither the code, the command nor
the table it draws.

References: the PNG text chunks as Pillow reads them (an independent PNG reader), the
command line as typed here, ``modalinfo.__version__``, and ``hashlib.sha256`` of the
``batch.csv`` bytes the plot draws.
"""

from __future__ import annotations

import hashlib
import json

import pytest
from PIL import Image

import modalinfo
from modalinfo.batch.report import plot_archive


def _rows():
    return [{"path": f"l{i}.npz", "analysis": "summary", "status": "ok", "units": "rad",
             "rms_total": 0.1 * (i + 1), "n_modes": 6, "rate": 500.0 + 100 * i}
            for i in range(3)]


def _description(path) -> dict:
    with Image.open(path) as im:
        return json.loads(im.info["Description"])


def test_plot_archive_writes_the_record_it_is_given(tmp_path):
    record = {"modalinfo": "9.9", "command": ["modalinfo", "batch", "x"], "n": 3}
    [path] = plot_archive(_rows(), tmp_path, provenance=record)
    assert _description(path) == record


def test_plot_archive_without_a_record_writes_none(tmp_path):
    [path] = plot_archive(_rows(), tmp_path)
    with Image.open(path) as im:
        assert "Description" not in im.info


def test_cli_batch_plots_name_version_command_and_table(client, tmp_path, helpers):
    pytest.importorskip("distributed")
    from modalinfo.cli import main

    root = tmp_path / "logs"
    root.mkdir()
    helpers.write_archive(root, n_good=3, corrupt=False)
    out = tmp_path / "out"
    argv = ["batch", str(root), "--scheduler", client.scheduler.address, "--analyses",
            "summary", "--out", str(out), "--quiet"]
    assert main(argv) == 0
    plots = sorted((out / "plots").glob("archive_vs_*.png"))
    assert plots
    table = hashlib.sha256((out / "batch.csv").read_bytes()).hexdigest()
    for path in plots:
        got = _description(path)
        assert got["command"][1:] == argv
        assert got["modalinfo"].startswith(modalinfo.__version__ + "+src.")
        assert got["table_sha256"] == table
