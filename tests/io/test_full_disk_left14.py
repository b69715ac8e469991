"""An HDF5 log written when the disk or the file-size limit runs out mid-write.

Issue 27, left14-h5: :func:`modalinfo.io.write_hdf5` (``modalinfo convert --to-fmt
hdf5``) let HDF5 write the staging file itself; a write failing as HDF5 closed the file
(its metadata, in the file's last kilobytes) made h5py's close fail and the interpreter
die of a segmentation fault, the staging file left behind (as ``closedloop run --out``,
left13-cli). The file is now built in memory and its bytes written through
``atomic_write``; a file whose datasets would not fit in memory is written by h5py on
disk through a file object that drops the writes of HDF5's close after a failed write.

Reference, outside the code: the kernel. ``RLIMIT_FSIZE`` (``ulimit -f``) makes every
write past the limit fail (``EFBIG``; Python ignores ``SIGXFSZ``), in a child process
(a segmentation fault must not end the test run), at every limit in the file's last
4 kB and a few earlier ones, on both paths (in memory; on disk, as for a file that
does not fit in memory, ``IMAGE_COPIES`` set to infinity); after each: one ``OSError``
line naming no staging file, the replaced file's SHA-256 unchanged (``hashlib``), no
``.tmp`` left (the folder's listing); the command line exits 2 with one stderr line.
Without a limit the bytes round-trip: ``h5py`` reads back the coefficients bit for bit,
on both paths.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from modalinfo.io import hdf5, read_hdf5, write_hdf5
from modalinfo.telemetry.log import ModalLog

_CHILD = """
import hashlib, io, os, resource, sys
from contextlib import redirect_stderr
import numpy as np
from modalinfo.cli import main
from modalinfo.io import write_hdf5
from modalinfo.telemetry.log import ModalLog

source, target = sys.argv[1], sys.argv[2]
if sys.argv[3] == "disk":  # as if the image did not fit in memory: h5py writes on disk
    import modalinfo.io.hdf5
    modalinfo.io.hdf5.IMAGE_COPIES = float("inf")
coeffs = np.random.default_rng(4).standard_normal((3000, 7))
log = ModalLog(coeffs, rate=500.0, units="rad", timestamps=np.arange(3000) / 500.0)
old = hashlib.sha256(open(target, "rb").read()).hexdigest()
size = os.path.getsize(source)


def check(limit, text):
    if "\\n" in text.strip() or ".tmp" in text:
        sys.exit(f"limit {limit}: {text!r}")
    if hashlib.sha256(open(target, "rb").read()).hexdigest() != old:
        sys.exit(f"limit {limit}: the old file changed")
    left = [n for n in os.listdir(os.path.dirname(target)) if n.endswith(".tmp")]
    if left:
        sys.exit(f"limit {limit}: left {left}")


def limited(limit, call):
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    try:
        return call()
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (resource.RLIM_INFINITY,) * 2)


limits = list(range(size - 4096, size - 16, 64)) + [size // 2, 1000]
for limit in limits:
    try:
        limited(limit, lambda: write_hdf5(log, target, overwrite=True))
    except OSError as exc:
        check(limit, str(exc))
    else:
        sys.exit(f"limit {limit}: written past the limit")
err = io.StringIO()
with redirect_stderr(err):
    code = limited(size - 1024, lambda: main(["convert", source, target, "--overwrite"]))
if code != 2:
    sys.exit(f"convert exited {code}: {err.getvalue()!r}")
check("convert", err.getvalue())
print(len(limits), "limits refused")
"""


def _log() -> ModalLog:
    coeffs = np.random.default_rng(4).standard_normal((3000, 7))
    return ModalLog(coeffs, rate=500.0, units="rad", timestamps=np.arange(3000) / 500.0)


def test_written_bytes_round_trip(tmp_path, monkeypatch):
    log = _log()
    for name in ("memory.h5", "disk.h5"):
        if name == "disk.h5":  # no memory for the image: HDF5 writes on disk, as before
            monkeypatch.setattr(hdf5, "IMAGE_COPIES", float("inf"))
        path = write_hdf5(log, tmp_path / name)
        with h5py.File(path, "r") as f:
            assert f["coefficients"][()].tobytes() == log.coeffs.tobytes()
            np.testing.assert_array_equal(f["timestamps"][()], log.timestamps)
        assert read_hdf5(path).coeffs.tobytes() == log.coeffs.tobytes()  # checksum verified
    assert sorted(os.listdir(tmp_path)) == ["disk.h5", "memory.h5"]


@pytest.mark.parametrize("where", ["memory", "disk"])
def test_file_size_limit_mid_write_is_one_error(where, tmp_path):
    source = write_hdf5(_log(), tmp_path / "source.h5")
    folder = tmp_path / "out"
    folder.mkdir()
    target = folder / "log.h5"
    target.write_bytes(b"the old file")  # replaced only by a whole new one
    old = hashlib.sha256(target.read_bytes()).hexdigest()
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])}
    child = subprocess.run([sys.executable, "-c", _CHILD, str(source), str(target), where],
                           capture_output=True, text=True, env=env, timeout=120)
    assert child.returncode == 0, (child.returncode, child.stdout, child.stderr[-2000:])
    assert child.stdout.strip().endswith("limits refused")
    assert hashlib.sha256(target.read_bytes()).hexdigest() == old
    assert os.listdir(folder) == ["log.h5"]
