"""`batch --no-plots` leaves no plot of another table in OUT/plots (round 54 PART b, P88).

Reference: the PNG record each summary plot carries (``Description`` JSON, read with
PIL) and ``hashlib.sha256`` of the table on disk. Before the fix a run with
``--set forecast.horizon=3 --no-plots`` into the folder of a horizon-2 run rewrote
``batch.csv`` and left ``plots/archive_vs_rate.png`` of the horizon-2 table beside it
(its ``table_sha256`` was the old table's). A plot drawn from the same table is kept.
"""

from __future__ import annotations

import hashlib
import json

from PIL import Image

from modalinfo.batch.report import plot_archive, remove_stale_plots


def _rows(rms: float) -> list[dict]:
    return [{"path": f"{name}.npz", "analysis": "summary", "status": "ok", "rate": rate,
             "rms_total": rms * k, "units": "rad", "n_modes": 10}
            for k, (name, rate) in enumerate((("a", 1000.0), ("b", 2000.0)), start=1)]


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def test_plot_of_another_table_removed(tmp_path):
    old = _sha("old table")
    drawn = plot_archive(_rows(1.0), tmp_path, provenance={"table_sha256": old})
    assert drawn == [tmp_path / "archive_vs_rate.png"]
    new = _sha("new table")
    assert remove_stale_plots(tmp_path, new) == drawn
    assert not (tmp_path / "archive_vs_rate.png").exists()


def test_plot_of_this_table_kept(tmp_path):
    same = _sha("table")
    drawn = plot_archive(_rows(1.0), tmp_path, provenance={"table_sha256": same})
    assert remove_stale_plots(tmp_path, same) == []
    with Image.open(drawn[0]) as image:
        assert json.loads(image.info["Description"])["table_sha256"] == same


def test_no_folder_no_error(tmp_path):
    assert remove_stale_plots(tmp_path / "plots", _sha("t")) == []


def test_analyse_archive_without_plots(tmp_path, client):
    import numpy as np

    from modalinfo.batch import analyse_archive
    from modalinfo.io import save
    from modalinfo.telemetry import ModalLog

    logs = tmp_path / "night"
    logs.mkdir()
    rng = np.random.default_rng(54)
    for name, rate in (("a.npz", 1000.0), ("b.npz", 2000.0)):
        save(ModalLog(rng.normal(size=(400, 4)), rate=rate, units="rad", wavelength=5e-7),
             logs / name)
    out = tmp_path / "out"
    first = analyse_archive(logs, "summary", out, client=client, progress=False)
    assert out / "plots" / "archive_vs_rate.png" in first.plots
    # another table in the same folder (a third log), without plots
    save(ModalLog(rng.normal(size=(400, 4)), rate=500.0, units="rad", wavelength=5e-7),
         logs / "c.npz")
    second = analyse_archive(logs, "summary", out, client=client, progress=False,
                             plots=False)
    table = hashlib.sha256((out / "batch.csv").read_bytes()).hexdigest()
    for png in (out / "plots").glob("*.png") if (out / "plots").exists() else ():
        with Image.open(png) as image:
            assert json.loads(image.info["Description"])["table_sha256"] == table, png
    assert out / "plots" / "archive_vs_rate.png" in second.removed_plots
