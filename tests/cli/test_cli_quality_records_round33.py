"""Round 33 PART b (issue 27): what the outlier policy did reaches every output, and
``select``'s gap refusal gives advice the command line can follow.

References (outside the code): the glitches planted in a seeded AR(1) log (phi 0.9,
3000 x 6: 8 single values at 1e3 and frames 100..109 at 5e2 in every mode, so 68
outlier values), read back from the files with ``json`` / ``csv``; ``select`` with
``--split-gaps`` on a log with a 50-frame hole against ``select`` on the longest
segment cut with numpy and saved as its own file (byte-equal printed table).

* B10 / B14: forecast.json, forecast.csv and reorder's ``--out`` JSON recorded
  ``--outliers clip`` only as a word of ``provenance.command``; they now hold
  ``quality`` (policy, counts, action) and forecast.csv a ``quality_action`` column.
* B37 / B38: ``batch --set summary.outliers=drop`` said "--outliers warn applied";
  the line now names the policy of each analysis from the rows.
* B26: ``select`` on a log with gaps advised "--max-frames or convert that part",
  which cannot reach a segment in the middle; it now names ``--split-gaps``, which
  ``select`` takes, and the advice run verbatim succeeds.
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.ordering.result import OrderingResult
from modalinfo.telemetry import ModalLog

T, M = 3000, 6
N_OUT = 8 + 10 * M  # planted outlier values


def _ar(seed: int, n: int = T) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, M)) * np.linspace(1.0, 0.3, M)
    x = np.zeros((n, M))
    for t in range(1, n):
        x[t] = 0.9 * x[t - 1] + e[t]
    return x


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    d = tmp_path_factory.mktemp("q33")
    x = _ar(0)
    rng = np.random.default_rng(3)
    frames = rng.choice(np.arange(300, T), 8, replace=False)
    x[frames, rng.integers(0, M, 8)] = 1e3
    x[100:110] = 5e2
    glitched = save(ModalLog(x, rate=1000.0, modes=list(range(2, 2 + M)), units="rad",
                             wavelength=5e-7), d / "gl.npz")
    clean = save(ModalLog(_ar(1), rate=1000.0, modes=list(range(2, 2 + M)), units="rad",
                          wavelength=5e-7), d / "ar.npz")
    return {"gl": glitched, "ar": clean, "dir": d}


def _run(capsys, argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_forecast_outputs_record_the_clip(logs, capsys):
    out = logs["dir"] / "fco"
    code, _, err = _run(capsys, ["forecast", logs["gl"], "--outliers", "clip",
                                 "--predictors", "linear", "--horizon", "1", "--out", out,
                                 "--quiet"])
    assert code == 0, err
    quality = json.loads((out / "forecast.json").read_text())["quality"]
    assert quality["policy"] == "clip" and quality["outlier_values"] == N_OUT
    assert quality["action"].startswith(f"clipped {N_OUT} outlier value(s)")
    assert "frames 100..109, 10 frames" in quality["action"]
    with open(out / "forecast.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert rows and {r["quality_action"] for r in rows} == {quality["action"]}
    # a clean log says so (the key is always there from the command line)
    code, _, err = _run(capsys, ["forecast", logs["ar"], "--predictors", "linear",
                                 "--horizon", "1", "--out", logs["dir"] / "fca", "--quiet"])
    assert code == 0, err
    clean = json.loads((logs["dir"] / "fca" / "forecast.json").read_text())["quality"]
    assert clean["action"] == "none (nothing flagged)" and clean["flagged_frames"] == 0


def test_reorder_json_records_the_clip_and_reads_back(logs, capsys):
    path = logs["dir"] / "rc.json"
    code, _, err = _run(capsys, ["reorder", logs["gl"], "--outliers", "clip", "--resamples",
                                 "0", "--budget", "20000", "--pupil-pixels", "32", "--out",
                                 path])
    assert code == 0, err
    quality = json.loads(path.read_text())["quality"]
    assert quality["policy"] == "clip" and quality["outlier_values"] == N_OUT
    assert quality["action"].startswith(f"clipped {N_OUT} outlier value(s)")
    assert OrderingResult.from_json(path).labels  # the reader ignores the new key


def _gapped(d):
    x = _ar(2, 2400)
    t = np.arange(2400) / 1000.0
    keep = np.ones(2400, dtype=bool)
    keep[900:950] = False  # a 50-frame hole: segments 0..899 and 950..2399
    log = ModalLog(x[keep], timestamps=t[keep], modes=list(range(2, 2 + M)), units="rad",
                   wavelength=5e-7)
    seg = ModalLog(x[950:], rate=1000.0, modes=list(range(2, 2 + M)), units="rad",
                   wavelength=5e-7)
    return save(log, d / "gap.npz"), save(seg, d / "seg.npz")


def test_select_gap_advice_runs_verbatim(logs, capsys):
    gap, seg = _gapped(logs["dir"])
    opts = ["--target", "Z2", "--max-lag", "3", "--surrogates", "19", "--no-intervals",
            "--max-inputs", "2"]
    code, _, err = _run(capsys, ["select", gap, *opts])
    assert code == 2 and len(err.splitlines()) == 1
    assert "pass --split-gaps" in err and "frames 900..2349" in err
    assert "convert that part" not in err
    code, out_split, err = _run(capsys, ["select", gap, *opts, "--split-gaps"])
    assert code == 0, err
    assert "analysed frames 900..2349 (1450 of 2350)" in err
    code, out_seg, err = _run(capsys, ["select", seg, *opts])
    assert code == 0, err
    # the same table as on the segment cut with numpy (bar the file name)
    assert out_split.replace("gap.npz", "seg.npz") == out_seg
    assert "Z2[t]" in out_split


def test_batch_line_names_the_policy_that_ran(logs, tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    from modalinfo.batch import analyse_archive

    src = tmp_path / "logs"
    src.mkdir()
    (src / "gl.npz").write_bytes(logs["gl"].read_bytes())
    out = tmp_path / "out"
    settings = {"summary": {"outliers": "drop"}}
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=":0") as client:
        analyse_archive(src, "summary", out, params=settings, client=client,
                        progress=False, plots=False)
    capsys.readouterr()
    code, _, err = _run(capsys, ["batch", src, "--out", out, "--no-plots", "--quiet",
                                 "--set", "summary.outliers=drop"])
    lines = err.splitlines()
    assert code == 0 and len(lines) == 1, err
    assert "outlier policy applied: summary: drop on 1 log(s)" in lines[0]
    assert "--outliers warn" not in lines[0] and "act on them" not in lines[0]  # as before
