"""Round 30 PART b (issue 27): an AOT export keeps the result's provenance record.

docs/ADVERSARIAL.md, "Round 30 PART b, issue 27", C05: ``closedloop export`` wrote the
version and seed in the ``MI_CLOOP`` card but dropped the result's record (Git commit,
config SHA-256, command line), so the exported file no longer said what made it.

References: the result file's own ``provenance`` attribute read with h5py (what
``closedloop run --out`` stored) and the card parsed with ``json`` from what
``aotpy.AOSystem.read_from_file`` reads back; a result saved without a record
(``provenance`` None, as before left28-prov) exports ``null``.
"""

from __future__ import annotations

import dataclasses
import json

import h5py
import pytest

aotpy = pytest.importorskip("aotpy")

from closedloop import SimulationResult  # noqa: E402
from closedloop.cli import main  # noqa: E402
from closedloop.config import save_config  # noqa: E402

from .conftest import small  # noqa: E402


def _card(path):
    system = aotpy.AOSystem.read_from_file(str(path))
    return json.loads(next(m.value for m in system.metadata if m.key == "MI_CLOOP"))


def test_export_keeps_the_run_record(tmp_path):
    config = tmp_path / "small.toml"
    save_config(small(), config)
    out = tmp_path / "run.h5"
    assert main(["run", "--config", str(config), "--duration", "0.004", "--seed", "3",
                 "--out", str(out), "--quiet"]) == 0
    with h5py.File(out, "r") as f:
        stored = json.loads(f.attrs["provenance"])
    fits = tmp_path / "run.fits"
    assert main(["export", str(out), str(fits)]) == 0
    card = _card(fits)
    assert card["provenance"] == stored
    assert card["provenance"]["command"][:2] == ["closedloop", "run"]

    # a result saved before the record existed
    older = dataclasses.replace(SimulationResult.load(out), provenance=None)
    fits2 = tmp_path / "old.fits"
    from closedloop.aot import export_aot

    export_aot(older, fits2)
    assert _card(fits2)["provenance"] is None
