"""left28-prov (issue 27): a closedloop result records what made it.

docs/ADVERSARIAL.md, "Round 27 PART b, issue 27", row P18: ``closedloop run --out``
recorded only ``version`` "0.1.0", the same over hundreds of commits. A result now
carries ``provenance``: the version number, the Git commit of the code, the SHA-256 of
the config and the seed (``closedloop run`` adds the command line).

References: ``git rev-parse HEAD`` of the checkout the code is imported from;
``hashlib.sha256`` of the config as the file stores it (``attrs["config"]``),
re-serialised here with sorted keys and no spaces; the seed and command the test gave;
the file's attributes read back with h5py. Integrity: the record is checksummed like the
other attributes (edited or removed: refused), while a file written before it existed
still loads (record None).
"""

from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
from pathlib import Path

import h5py
import pytest

import modalinfo
from closedloop import SimulationResult, simulate
from closedloop.cli import main
from closedloop.config import save_config

from .conftest import small


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    folder = tmp_path_factory.mktemp("prov")
    config = folder / "small.toml"
    save_config(small(), config)
    out = folder / "run.h5"
    argv = ["run", "--config", str(config), "--duration", "0.02", "--seed", "5", "--out",
            str(out), "--quiet"]
    assert main(argv) == 0
    return out, argv


def test_run_out_records_version_commit_config_hash_seed_and_command(saved, capsys):
    out, argv = saved
    with h5py.File(out, "r") as f:
        record = json.loads(f.attrs["provenance"])
        stored = json.loads(f.attrs["config"])
    assert record["modalinfo"] == modalinfo.__version__
    assert record["seed"] == 5
    assert record["command"] == ["closedloop", *argv]
    canonical = json.dumps(stored, sort_keys=True, separators=(",", ":"))
    assert record["config_sha256"] == hashlib.sha256(canonical.encode()).hexdigest()
    top = Path(modalinfo.__file__).resolve().parents[1]
    if shutil.which("git") and (top / ".git").exists():
        head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=top, capture_output=True,
                              text=True, check=True).stdout.strip()
        edited = subprocess.run(  # left30-prov: edits not committed are marked "-dirty"
            ["git", "status", "--porcelain", "--untracked-files=no", "--", "modalinfo",
             "closedloop", "paper_figures"], cwd=top, capture_output=True, text=True,
            check=True).stdout.strip()
        assert record["git"] == head + ("-dirty" if edited else "")
    assert SimulationResult.load(out).provenance == record


def test_library_result_records_the_same_without_a_command(saved):
    out, _ = saved
    direct = simulate(small(), 0.02, seed=5, progress=False)
    with h5py.File(out, "r") as f:
        record = json.loads(f.attrs["provenance"])
    assert direct.provenance == {k: v for k, v in record.items() if k != "command"}
    other = simulate(small(), 0.02, seed=6, progress=False)
    assert other.provenance["seed"] == 6
    assert other.provenance["config_sha256"] == direct.provenance["config_sha256"]


def test_record_is_checksummed_and_older_files_still_load(saved, tmp_path):
    out, _ = saved
    good = out.read_bytes()
    path = tmp_path / "r.h5"
    for edit in ("change", "remove"):
        path.write_bytes(good)
        with h5py.File(path, "r+") as f:
            if edit == "change":
                f.attrs["provenance"] = f.attrs["provenance"].replace('"seed":5', '"seed":6')
            else:
                del f.attrs["provenance"]
        with pytest.raises(ValueError, match="the attribute 'provenance' "
                           + ("does not match" if edit == "change" else "is missing")):
            SimulationResult.load(path)
    # a file written before results carried the record
    import dataclasses

    old = dataclasses.replace(SimulationResult.load(out), provenance=None)
    old.save(tmp_path / "old.h5")
    with h5py.File(tmp_path / "old.h5", "r") as f:
        assert "provenance" not in f.attrs
    assert SimulationResult.load(tmp_path / "old.h5").provenance is None
