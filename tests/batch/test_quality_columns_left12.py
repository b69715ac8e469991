"""``modalinfo batch``'s rows carry every field of the quality report, through Parquet and CSV.

Issue 27, leftovers 12-cli item 5. References, outside the batch code:
- the fields ``modalinfo info``'s quality pass reports for each file, from
  ``assess_quality(load(path))`` called here (``QualityReport.to_dict``), each of which
  must be a column ``quality_<field>`` holding the same value;
- facts planted in the logs: one glitched frame (100 sigma in every mode) and 10 stuck
  values in a 4000-frame white log; the second half of another scaled by sqrt(7.4) (a
  seeing change: not stationary, its block scale ratio near sqrt(7.4) = 2.7); a 10-frame
  log (too short to assess: ``assessed`` False, a note, no ``k``); an AR(1) log with
  every pair of frames written in reverse order and one with its last 1000 frames
  appended again (fix34-b: columns ``quality_pair_order`` and ``quality_copied_*``,
  present in every row);
- the tables read back by pyarrow.parquet and by the standard library's ``csv`` module.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from modalinfo.io import load, save
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.quality import assess_quality


@pytest.fixture(scope="module")
def batch(tmp_path_factory):
    distributed = pytest.importorskip("distributed")
    pytest.importorskip("pyarrow")
    from modalinfo.batch import analyse_archive

    src = tmp_path_factory.mktemp("quality_logs")
    rng = np.random.default_rng(12)
    glitch = rng.standard_normal((4000, 6)) * 0.1
    glitch[1234] += 10.0  # 100 sigma in every mode: one glitched frame
    glitch[2000:2010, 3] = glitch[2000, 3]  # 10 equal values: a stuck run
    seeing = rng.standard_normal((4000, 6))
    seeing[2000:] *= math.sqrt(7.4)
    short = rng.standard_normal((10, 6))
    ar = np.zeros((4000, 6))
    e = rng.standard_normal((4000, 6))
    for t in range(1, 4000):
        ar[t] = 0.95 * ar[t - 1] + e[t]
    swapped = ar.copy()
    swapped[0::2], swapped[1::2] = ar[1::2], ar[0::2]
    copied = np.vstack([ar, ar[3000:]])
    for name, x in (("glitch", glitch), ("seeing", seeing), ("short", short),
                    ("swapped", swapped), ("copied", copied)):
        save(ModalLog(x, rate=1000.0, wavelength=5e-7), src / f"{name}.npz")
    out = tmp_path_factory.mktemp("quality_out") / "out"
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=":0") as client:
        result = analyse_archive(src, "summary", out, client=client, progress=False,
                                 plots=False)
    assert [r["status"] for r in result.rows] == ["ok"] * 5
    return src, result


def _expected(path) -> dict:
    fields = assess_quality(load(path)).to_dict()
    fields["worst_modes"] = ", ".join(f"{k} {c}" for k, c in fields["worst_modes"].items())
    return {"assessed": True, "note": "", "repeated_frames": 0, "copied_frames": 0,
            "copied_block": "", "pair_order": "", "outlier_rows": "", "stuck_rows": "",
            "upsampled": "", "filled_rows": "", **fields}  # the last two: fix57-c


def _by_name(rows) -> dict:
    return {r["path"].rsplit("/", 1)[-1].split(".")[0]: r for r in rows}


def test_every_report_field_is_a_column_with_its_value(batch):
    src, result = batch
    rows = _by_name(result.rows)
    for name, row in rows.items():
        expected = _expected(src / f"{name}.npz")
        got = {key[len("quality_"):]: value for key, value in row.items()
               if key.startswith("quality_") and key != "quality_action"}
        assert got == expected, name
    # the planted facts, read from the columns
    assert rows["glitch"]["quality_glitched_frames"] == 1
    assert rows["glitch"]["quality_stuck_values"] == 10
    assert rows["glitch"]["quality_stationary"] is True
    assert rows["seeing"]["quality_stationary"] is False
    assert rows["seeing"]["quality_scale_ratio"] == pytest.approx(math.sqrt(7.4), rel=0.15)
    assert "seeing not steady" in rows["seeing"]["quality_note"]
    assert rows["short"]["quality_assessed"] is False and rows["short"]["quality_k"] is None
    assert rows["short"]["quality_note"].startswith("too short to assess")
    assert rows["swapped"]["quality_pair_order"].startswith("lag-1")
    assert rows["glitch"]["quality_pair_order"] == ""
    assert rows["copied"]["quality_copied_frames"] == 1000
    assert rows["copied"]["quality_copied_block"] == "4000-4999 = 3000-3999"
    assert rows["glitch"]["quality_copied_frames"] == 0


def test_parquet_and_csv_round_trip(batch):
    import pyarrow.parquet as pq

    src, result = batch
    rows = _by_name(result.rows)
    parquet = _by_name(pq.read_table(result.parquet_path).to_pylist())
    with open(result.csv_path, newline="", encoding="utf-8") as fh:
        text = _by_name(list(csv.DictReader(fh)))
    names = sorted(_by_name(result.rows))
    assert sorted(parquet) == sorted(text) == names
    for name in names:
        for key, value in rows[name].items():
            if not key.startswith("quality_"):
                continue
            back, cell = parquet[name][key], text[name][key]
            if value is None:
                assert back is None and cell == "", (name, key)
            elif isinstance(value, bool):
                assert back is value and cell == str(value).lower(), (name, key)
            elif isinstance(value, float):
                assert back == value and float(cell) == pytest.approx(value, rel=1e-12)
            else:
                assert back == value and cell == str(value), (name, key)
