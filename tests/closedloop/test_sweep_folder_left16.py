"""Leftovers 16-dask (issue 27), sweep #11: a folder holding only ``runs/`` is resumed.

A sweep interrupted before its first row left ``runs/`` alone (its empty ``rows/``
removed on leaving while a worker still saved a run, or recreated by a worker that
outlived its client with ``mkdir(parents=True)``) and the next sweep refused the folder
as "not its own".

Reference from outside the code: the file system (``os.path.exists`` of the folders a
worker may create) and the refusal's documented rule (a non-empty folder with neither
``rows/`` nor ``runs/`` is someone else's).
"""

from __future__ import annotations

import types

import pytest

pytest.importorskip("distributed")

from closedloop import sweep as sweep_mod  # noqa: E402
from modalinfo.common.folders import OutputError  # noqa: E402

GRID = {"preset": "kaos", "duration": 0.01, "seeds": [0], "predictors": ["none"],
        "overrides": [{"name": "base"}]}


class _StartedError(Exception):
    """Raised in place of starting a cluster: the folder was accepted."""


def _no_cluster(*_args, **_kwargs):
    raise _StartedError


def test_a_folder_holding_only_runs_is_resumed_not_refused(tmp_path, monkeypatch):
    import modalinfo.common.tasks.cluster as cluster

    monkeypatch.setattr(cluster, "open_client", _no_cluster)
    out = tmp_path / "so"
    (out / "runs").mkdir(parents=True)
    (out / "runs" / "0123.h5").write_bytes(b"\x89HDF\r\n\x1a\n")
    with pytest.raises(_StartedError):
        sweep_mod.sweep(GRID, out, progress=False)
    assert (out / "runs" / "0123.h5").read_bytes() == b"\x89HDF\r\n\x1a\n"


def test_a_foreign_folder_is_still_refused(tmp_path, monkeypatch):
    import modalinfo.common.tasks.cluster as cluster

    monkeypatch.setattr(cluster, "open_client", _no_cluster)
    out = tmp_path / "so"
    (out / "results").mkdir(parents=True)
    with pytest.raises(OutputError, match=r"not empty and holds no earlier"):
        sweep_mod.sweep(GRID, out, progress=False)


def test_a_worker_never_recreates_a_removed_sweep_folder(tmp_path, monkeypatch):
    import closedloop.training as training

    saved = []
    result = types.SimpleNamespace(summary=lambda: {"strehl": 0.5}, budget=None,
                                   save=lambda path, overwrite: saved.append(path))
    monkeypatch.setattr(training, "run_trained", lambda *a, **k: result)
    config = sweep_mod.sweep_specs(GRID)[0].payload["config"]
    gone = tmp_path / "so"  # removed after the client was interrupted
    payload = {"config": config, "predictor": "none", "duration": 0.01, "seed": 0,
               "out_dir": str(gone), "key": "k"}
    with pytest.raises(FileNotFoundError):
        sweep_mod.run_one(payload)
    assert not gone.exists() and saved == []
    gone.mkdir()  # the folder present: runs/ made once, the run saved
    assert sweep_mod.run_one(payload)["result_file"] == str(gone / "runs" / "k.h5")
    assert saved == [gone / "runs" / "k.h5"]
