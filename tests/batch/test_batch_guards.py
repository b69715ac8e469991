"""Guard rails of ``modalinfo batch``: refusals before work, the output lock, exit codes,
progress lines and the bounded wait for workers.

References: the rules as documented (a bad ``--set`` value, a memory limit below
``MIN_MEMORY_LIMIT`` and a folder in use are refused before anything is computed or
written: the output folder is checked to be absent or unchanged); a memory limit
``distributed.worker_memory.parse_memory_limit`` resolves to enough memory (1 = the
whole machine) is accepted; the lock's holder
is a real process of this host (``os.kill(pid, 0)`` tells alive from dead, checked
independently in each test with a subprocess we start and reap); the exit status and
the failed-row count are compared with the rows of the table written (counted in the
test from ``batch.csv``); the progress lines with the number of specs given; the
no-worker wait with a real scheduler that has no worker (``distributed.LocalCluster``
with ``n_workers=0``), bounded by ``worker_wait``.
"""

from __future__ import annotations

import csv
import json
import os
import socket
import subprocess
import sys
import time

import pytest

pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

from modalinfo.batch.engine import (  # noqa: E402
    NoWorkersError,
    OutputInUseError,
    OutputLock,
    RowStore,
    TaskSpec,
    check_memory_limit,
    run_tasks,
)
from modalinfo.cli import main  # noqa: E402


def _dead_pid() -> int:
    """The pid of a process that has exited and been reaped."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait(timeout=60)
    with pytest.raises(ProcessLookupError):
        os.kill(proc.pid, 0)
    return proc.pid


@pytest.fixture
def live_pid():
    """A live process of this host for as long as the test runs."""
    # alive until killed (it waits on its stdin), not for a time the test might outlast
    proc = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"],
                            stdin=subprocess.PIPE)
    yield proc.pid
    proc.kill()
    proc.wait(timeout=60)
    proc.stdin.close()


def _write_lock(folder, pid, host=None):
    folder.mkdir(exist_ok=True)
    (folder / OutputLock.NAME).write_text(json.dumps(
        # written now, after ``pid`` started (a lock older than its holder's process
        # names a reused pid and is stale: round 15 PART b, F10)
        {"pid": pid, "host": host or socket.gethostname(), "started": time.time(),
         "command": "modalinfo batch"}))


# ----------------------------------------------------------------------- refusals
@pytest.mark.parametrize("setting, message", [
    ("forecast.horizon=0", "forecast.horizon must be an int >= 1; got 0"),
    ("forecast.horizon=2.5", "forecast.horizon must be an int; got 2.5"),
    ("forecast.predictors=linear,crystal-ball", "'crystal-ball' is not a predictor"),
    ("forecast.train=1.0", "forecast.train must be < 1.0"),
    ("forecast.modes=9-3", "range '9-3' is decreasing"),
])
def test_bad_set_values_are_refused_before_any_work(tmp_path, capsys, helpers, setting,
                                                    message):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    out = tmp_path / "out"
    code = main(["batch", str(tmp_path), "--analyses", "forecast", "--set", setting,
                 "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and message in err, err
    assert not out.exists()


@pytest.mark.parametrize("analysis, params, message", [
    ("ordering", {"method": "astrology"}, "ordering.method must be one of"),
    ("ordering", {"seeds": []}, "ordering.seeds must be a non-empty JSON list"),
    ("ordering", {"pupil_pixels": 2}, "ordering.pupil_pixels must be an int >= 4"),
    ("fitting_error", {"fraction": 1.5}, "fitting_error.fraction must be <= 1.0"),
    ("fitting_error", {"orderings": "zernike"}, "must look like basis:method"),
    ("summary", {"chunk_frames": -1}, "summary.chunk_frames must be an int >= 1"),
])
def test_every_analysis_checks_its_values(analysis, params, message):
    from modalinfo.batch.analyses import DEFAULTS, resolve_params

    with pytest.raises(ValueError, match=message.replace(".", r"\.").replace("(", r"\(")):
        resolve_params(analysis, params)
    for name in DEFAULTS:  # the defaults pass their own checks
        assert resolve_params(name, DEFAULTS[name]) == DEFAULTS[name]


@pytest.mark.parametrize("limit, message", [
    ("10MB", "at least 384.00 MiB"),
    ("200 MiB", "at least 384.00 MiB"),
    ("-2GB", "must be a size such as"),
    ("plenty", "must be a size such as"),
])
def test_memory_limit_a_worker_cannot_run_under_is_refused(tmp_path, capsys, helpers,
                                                           limit, message):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    out = tmp_path / "out"
    code = main(["batch", str(tmp_path), "--out", str(out), f"--memory-limit={limit}"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and message in err and "--memory-limit" in err
    assert not out.exists()


def test_memory_limits_dask_accepts_pass():
    for limit in (None, "auto", 0, "0", "1GB", "512 MiB", 0.5, 2**30):
        check_memory_limit(limit)


@pytest.mark.parametrize("limit", [1, 1.0, "1", "1.0"])
def test_memory_limit_one_is_the_whole_machine_as_in_dask(limit):
    # distributed reads a number in (0, 1] as a fraction of the machine's memory, so 1 is
    # all of it (not one byte); the check must accept what distributed resolves to that
    import logging

    from distributed.worker_memory import parse_memory_limit

    from modalinfo.batch.engine import MIN_MEMORY_LIMIT

    resolved = parse_memory_limit(limit, 1, logger=logging.getLogger(__name__))
    assert resolved >= MIN_MEMORY_LIMIT  # this machine has more than 384 MiB
    check_memory_limit(limit)


def test_output_checks_before_work(tmp_path, capsys, helpers, monkeypatch):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    a_file = tmp_path / "notes.txt"
    a_file.write_text("mine")
    for out, needle in ((a_file, "is not a directory"),
                        (a_file / "sub", "is not a directory"),
                        (tmp_path / "no" / "such" / "out", "does not exist")):
        assert main(["batch", str(tmp_path), "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and needle in err, err
    assert a_file.read_text() == "mine"
    # a nearly full file system: refused, naming the free space
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda _: usage(10**9, 10**9 - 2**20, 2**20))
    assert main(["batch", str(tmp_path), "--out", str(tmp_path / "new")]) == 2
    assert "1.00 MiB free" in capsys.readouterr().err
    assert not (tmp_path / "new").exists()


# ----------------------------------------------------------------------- the lock
def test_lock_records_its_holder_and_excludes_a_second_holder(tmp_path):
    with OutputLock(tmp_path, "modalinfo batch") as lock:
        holder = json.loads(lock.path.read_text())
        assert holder["pid"] == os.getpid() and holder["host"] == socket.gethostname()
        with pytest.raises(OutputInUseError, match=f"pid {os.getpid()}"):
            OutputLock(tmp_path, "closedloop sweep").acquire()
    assert not (tmp_path / OutputLock.NAME).exists()
    assert list(tmp_path.iterdir()) == []  # no temporary file left either


def test_lock_of_a_live_process_keeps_a_second_batch_out(tmp_path, capsys, helpers,
                                                         live_pid):
    helpers.write_archive(tmp_path, n_good=2, corrupt=False)
    out = tmp_path / "out"
    _write_lock(out, live_pid)
    code = main(["batch", str(tmp_path), "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "is in use" in err and f"pid {live_pid}" in err and ".lock" in err
    assert sorted(p.name for p in out.iterdir()) == [OutputLock.NAME]  # nothing computed
    # a lock written on another host cannot be checked from here: in use too
    _write_lock(out, _dead_pid(), host="some-other-node")
    with pytest.raises(OutputInUseError, match="some-other-node"):
        OutputLock(out).acquire()


def test_stale_lock_of_a_dead_process_is_taken_over(tmp_path, client, helpers):
    from modalinfo.batch import analyse_archive

    helpers.write_archive(tmp_path, n_good=3, corrupt=False)
    out = tmp_path / "out"
    _write_lock(out, _dead_pid())
    result = analyse_archive(tmp_path, "summary", out, client=client, progress=False)
    assert result.n_ok == 3 and result.report.n_submitted == 3
    assert not (out / OutputLock.NAME).exists()  # released at the end


# ----------------------------------------------------------------------- exit codes
def test_failed_rows_give_exit_1_and_their_count(tmp_path, capsys, client, helpers):
    from modalinfo.batch import analyse_archive

    helpers.write_archive(tmp_path, n_good=4, corrupt=True)  # 4 logs + 3 broken files
    out = tmp_path / "out"
    analyse_archive(tmp_path, "summary", out, client=client, progress=False)
    capsys.readouterr()
    # the same command resumes (no task left: no cluster) and reports the table's state
    code = main(["batch", str(tmp_path), "--out", str(out), "--no-plots"])
    captured = capsys.readouterr()
    with open(out / "batch.csv", newline="") as fh:
        statuses = [row["status"] for row in csv.DictReader(fh)]
    failed = sum(s != "ok" for s in statuses)
    assert failed == 3 and len(statuses) == 7
    assert code == 1
    assert f"modalinfo batch: {failed} of {len(statuses)} rows failed" in captured.err
    # an archive of good logs only: 0
    good = tmp_path / "good"
    good.mkdir()
    helpers.write_archive(good, n_good=2, corrupt=False)
    analyse_archive(good, "summary", tmp_path / "out2", client=client, progress=False)
    assert main(["batch", str(good), "--out", str(tmp_path / "out2"), "--no-plots"]) == 0


# ----------------------------------------------------------------------- progress, workers
def test_progress_lines_when_stderr_is_not_a_terminal(tmp_path, capsys, client):
    def _square(payload: dict) -> dict:  # local: pickled by value for the workers
        return {"value": payload["x"] ** 2}

    specs = [TaskSpec(f"k{i:02d}", {"x": i}, {"i": i}) for i in range(6)]
    report = run_tasks(specs, _square, RowStore(tmp_path), client, progress=True,
                       progress_every=0.0, name="test batch")
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.startswith("test batch: ")]
    assert report.n_ok == 6 and lines
    assert lines[-1].startswith("test batch: 6/6 tasks done (6 ok, 0 error, 0 lost)")
    done = [int(ln.split()[2].split("/")[0]) for ln in lines]
    assert done == sorted(done)  # counts only grow
    assert sorted(r["value"] for r in RowStore(tmp_path).rows()) == [i * i for i in range(6)]


def test_no_worker_gives_a_notice_then_an_error_and_keeps_nothing_half_done(tmp_path,
                                                                            capsys):
    import distributed

    def _square(payload: dict) -> dict:
        return {"value": payload["x"] ** 2}

    specs = [TaskSpec(f"k{i}", {"x": i}) for i in range(3)]
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=":0") \
            as cluster, distributed.Client(cluster) as no_workers:
        with pytest.raises(NoWorkersError, match="no Dask worker ran a task for"):
            run_tasks(specs, _square, RowStore(tmp_path), no_workers, progress=False,
                      worker_wait=1.5)
    err = capsys.readouterr().err
    assert "no Dask worker is running" in err and "waiting up to 1.5 s" in err
    assert RowStore(tmp_path).rows() == []  # no row invented for tasks that never ran


def test_cli_on_a_scheduler_without_workers_exits_1(tmp_path, capsys, helpers):
    import distributed

    helpers.write_archive(tmp_path, n_good=2, corrupt=False)
    out = tmp_path / "out"
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=":0") \
            as cluster:
        code = main(["batch", str(tmp_path), "--out", str(out), "--scheduler",
                     cluster.scheduler_address, "--worker-wait", "1", "--quiet"])
    err = capsys.readouterr().err
    assert code == 1
    assert err.strip().splitlines()[-1].startswith("modalinfo batch: error: no Dask worker")
    assert not (out / OutputLock.NAME).exists()  # the lock is released on the way out


# ----------------------------------------------------------------------- manifests
def test_manifest_takes_the_transpose_dataset_and_loop_hints_of_the_cli(tmp_path, helpers):
    import numpy as np

    from modalinfo.batch.manifest import collect_logs
    from modalinfo.io import load

    x = helpers.make_log(3, n_frames=40, n_modes=5).coeffs
    np.save(tmp_path / "wide.npy", np.ascontiguousarray(x.T))  # modes x frames
    np.savez(tmp_path / "two.npz", calib=np.eye(3), coeffs=x)
    (tmp_path / "m.csv").write_text("path,transpose,dataset,rate\n"
                                    "wide.npy,true,,500\n"
                                    "two.npz,,coeffs,500\n")
    entries = {e.path.rsplit("/", 1)[1]: e for e in collect_logs(tmp_path / "m.csv")}
    assert entries["wide.npy"].hints == {"transpose": True, "rate": 500.0}
    assert entries["two.npz"].hints == {"dataset": "coeffs", "rate": 500.0}
    for entry in entries.values():  # the hints give what load gives with them
        log = load(entry.path, fmt=entry.fmt, **entry.hints)
        np.testing.assert_array_equal(log.coeffs, x)
    (tmp_path / "bad.csv").write_text("path,transpose\nwide.npy,maybe\n")
    with pytest.raises(ValueError, match="column 'transpose' must be true or false"):
        collect_logs(tmp_path / "bad.csv")
    (tmp_path / "aot.csv").write_text("path,loop\nwide.npy,dm0\n")
    assert collect_logs(tmp_path / "aot.csv")[0].hints == {"loop": "dm0"}


def test_a_manifest_without_a_path_column_is_not_read_as_a_log(tmp_path, helpers):
    import numpy as np

    from modalinfo.batch.manifest import collect_logs

    (tmp_path / "files.csv").write_text("file,rate\nnight1.h5,1000\nnight2.fits,1000\n")
    with pytest.raises(ValueError, match="names files .'night1.h5'. like a manifest but "
                                         "its header has no 'path' column"):
        collect_logs(tmp_path / "files.csv")
    # a numeric CSV log (header of mode labels) is still a log
    np.savetxt(tmp_path / "log.csv", helpers.make_log(0, 20, 3).coeffs, delimiter=",",
               header="Z2,Z3,Z4", comments="")
    (entry,) = collect_logs(tmp_path / "log.csv")
    assert entry.path == str((tmp_path / "log.csv").resolve())


def test_a_scheduler_that_cannot_be_reached_leaves_no_folder(tmp_path, capsys, helpers):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    out = tmp_path / "out"
    assert main(["batch", str(tmp_path), "--out", str(out), "--scheduler", "no-port-here",
                 "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no-port-here" in err
    assert not out.exists()
