"""Inputs shared by the command-line tests (reference: none; inputs and a helper only).

- :func:`write_small_log`: the small log the refusal tests run on, and the fixture
  ``make_small_log`` that writes it into the test's ``tmp_path`` (each test file keeps
  its own frame count);
- :func:`exit_code`: ``modalinfo.cli.main``'s status, returned or raised;
- :func:`batch_stand_in`: what ``modalinfo.batch.analyse_archive`` returns, for a test
  that replaces it to judge batch's printed lines on given rows.

Test files import the functions (``from .conftest import exit_code``); pytest's
importlib mode gives them the module pytest loaded, so there is one copy.
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def write_small_log(path: Path, frames: int) -> Path:
    """Write a ``frames``-frame log of Z2-Z4 to ``path`` (.npz) and return its path.

    A random walk (cumulative sum of seed-0 standard normals, times 0.01 rad) at 2 kHz:
    small, smooth, the same bits for the same ``frames``.
    """
    rng = np.random.default_rng(0)
    coeffs = np.cumsum(rng.standard_normal((frames, 3)), axis=0) * 0.01
    return save(ModalLog(coeffs, rate=2000.0, modes=[2, 3, 4], units="rad"), path)


@pytest.fixture
def make_small_log(tmp_path):
    """``make_small_log(frames)``: :func:`write_small_log` into ``tmp_path / "log.npz"``."""
    return lambda frames: write_small_log(tmp_path / "log.npz", frames)


def exit_code(argv) -> int:
    """``main``'s status, returned or raised (argparse errors raise SystemExit).

    Every item of ``argv`` is passed as ``str`` (paths and numbers may be given as such).
    """
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:
        return exc.code


def batch_stand_in(rows: list[dict], out: Path, skipped=(), plots=()) -> SimpleNamespace:
    """An ``analyse_archive`` result of ``rows`` written into ``out`` (batch's --out).

    Every row was run now (none skipped); a row whose ``status`` is not ``"ok"`` counts
    as an error row.
    """
    n_ok = sum(r.get("status") == "ok" for r in rows)
    report = SimpleNamespace(n_specs=len(rows), n_skipped=0, n_submitted=len(rows),
                             n_ok=n_ok, n_error=len(rows) - n_ok, n_lost=0, elapsed=0.1)
    return SimpleNamespace(identical=[], skipped=list(skipped), unreadable=[], rows=rows,
                           report=report, n_ok=n_ok, n_error=len(rows) - n_ok,
                           csv_path=out / "batch.csv", parquet_path=out / "batch.parquet",
                           plots=list(plots))
