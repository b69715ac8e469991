"""Leftovers 18-sigint (issue 27): a Ctrl-C while batch writes its table.

A Ctrl-C while ``modalinfo batch`` wrote its table or plots was only recorded by the
handler that lives with the Dask client (Leftovers 17-sigint) and acted on once every
write had finished. The client is now closed before the writes, so a Ctrl-C ends the
write at once; the writes are atomic (temporary file + rename), so the folder keeps
the old table or none, and no temporary file. ``closedloop sweep`` shares the client's
handler: a Ctrl-C that lands inside a ``gc`` callback (distributed registers one) is
honoured there too (checked by hand only in Leftovers 17-sigint).

Reference from outside the code: the signal as POSIX delivers it (``os.killpg``, the
terminal's Ctrl-C to the foreground process group); the exit status by the
shell's convention (128 + SIGINT = 130); the folder read with ``os.listdir`` and the old
table compared byte for byte; resume checked by running the same command again (exit
0, a table with an ok row per task). No timing race: the write waits on a file the test
never creates (it signals its readiness through another file), so the SIGINT arrives
at a fixed point; the bound on the wait for the exit (60 s) only turns "never acted on
during the write" into a failure.
"""

from __future__ import annotations

import csv
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("distributed")
pytest.importorskip("pyarrow")

ROOT = Path(__file__).resolve().parents[2]

posix = pytest.mark.skipif(os.name != "posix" or not hasattr(os, "killpg"),
                           reason="POSIX process groups and signals")

#: The batch with ``pyarrow.parquet.write_table`` (the first table write, inside
#: ``atomic_write``) touching READY, then waiting on GO, which the test never creates.
WRITE_DRIVER = '''
import os, sys, time
import pyarrow.parquet as pq

_write = pq.write_table

def write_table(*args, **kwargs):
    open(os.environ["READY"], "w").close()
    while not os.path.exists(os.environ["GO"]):
        time.sleep(0.01)
    return _write(*args, **kwargs)

pq.write_table = write_table
if __name__ == "__main__":
    from modalinfo.cli import main
    sys.exit(main(sys.argv[1:]))
'''

def _env(tmp_path: Path) -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1",
            "READY": str(tmp_path / "ready"), "GO": str(tmp_path / "go")}


def _interrupted_in_the_write(tmp_path: Path, args: list[str]) -> tuple[int, str]:
    """Run the write driver, SIGINT its group once the table write waits; (rc, stderr)."""
    ready = tmp_path / "ready"
    ready.unlink(missing_ok=True)
    proc = subprocess.Popen([sys.executable, str(tmp_path / "drv.py"), *args], cwd=tmp_path,
                            env=_env(tmp_path), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 240
        while not ready.exists():
            assert proc.poll() is None, proc.communicate()[1]
            assert time.monotonic() < deadline, "the table write never started"
            time.sleep(0.05)
        os.killpg(proc.pid, signal.SIGINT)
        try:
            _, err = proc.communicate(timeout=60)
        except subprocess.TimeoutExpired:  # still waiting: the Ctrl-C was only recorded
            (tmp_path / "go").touch()
            _, err = proc.communicate(timeout=120)
            pytest.fail(f"the Ctrl-C was acted on only after the write (exit "
                        f"{proc.returncode}, {err!r})")
        return proc.returncode, err
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def _table_rows(path: Path) -> list[dict]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


@posix
def test_ctrl_c_during_the_table_write_ends_it_at_once(tmp_path, helpers):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    (tmp_path / "drv.py").write_text(WRITE_DRIVER)
    out = tmp_path / "out"
    args = ["batch", str(tmp_path / "log000.npz"), "--out", str(out), "--workers", "1",
            "--quiet", "--no-plots"]
    # a new folder: the table is absent after the Ctrl-C, the rows kept, no temporary
    rc, err = _interrupted_in_the_write(tmp_path, args)
    assert (rc, err) == (130, "modalinfo: interrupted\n"), err
    left = sorted(os.listdir(out))
    assert not [n for n in left if n.startswith("batch.") or n.endswith(".tmp")], left
    assert os.listdir(out / "rows"), left
    again = subprocess.run([sys.executable, "-m", "modalinfo", *args], cwd=tmp_path,
                           env=_env(tmp_path), capture_output=True, text=True, timeout=240)
    assert again.returncode == 0, again.stderr
    rows = _table_rows(out / "batch.csv")
    assert rows and all(r["status"] == "ok" for r in rows)
    # a complete folder (no cluster started): the old table is kept byte for byte
    old = {n: (out / n).read_bytes() for n in ("batch.csv", "batch.parquet")}
    rc, err = _interrupted_in_the_write(tmp_path, args)
    assert (rc, err) == (130, "modalinfo: interrupted\n"), err
    assert {n: (out / n).read_bytes() for n in old} == old
    assert not [n for n in os.listdir(out) if n.endswith(".tmp")]
