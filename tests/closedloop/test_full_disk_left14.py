"""A run file written when the disk or the file-size limit runs out mid-write.

Issue 27, left14-h5 (left over by left13-cli): ``closedloop run --out`` on a disk that
filled while HDF5 wrote ended in h5py's ``RuntimeError: Can't decrement id ref count``
naming the staging file ``.run.h5.<pid>-<random>.tmp``, then a segmentation fault, the
staging file left behind; a little earlier in the file, a 41-line traceback of an HDF5
``RuntimeError`` (not an ``OSError``: the command lines' one-line rule missed it). The
file is now built in memory and its bytes written through ``atomic_write``.

Reference, outside the code: the kernel. ``RLIMIT_FSIZE`` (``ulimit -f``) makes every
write past the limit fail (``EFBIG``; Python ignores ``SIGXFSZ``) exactly where a full
disk fails one, in a child process (a segmentation fault must not end the test run),
at every limit in the file's last 4 kB (HDF5's metadata written as it closes: the
fault) and at a few earlier ones, on both paths: the file built in memory, and written
by h5py on disk (as for a file that does not fit in memory, ``IMAGE_COPIES`` set to
infinity). After each failure: an ``OSError`` of one line naming
no staging file, the replaced file's SHA-256 unchanged (``hashlib``), no ``.tmp`` left
(the folder's listing). Without a limit the bytes round-trip (``h5py`` reads back what
was saved, the simulated arrays bit for bit).
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

from closedloop import SimulationResult, simulate

from .conftest import small

_CHILD = """
import hashlib, os, resource, sys
from closedloop.result import SimulationResult

source, target = sys.argv[1], sys.argv[2]
if sys.argv[3] == "disk":  # as if the image did not fit in memory: h5py writes on disk
    import modalinfo.io.hdf5
    modalinfo.io.hdf5.IMAGE_COPIES = float("inf")
old = hashlib.sha256(open(target, "rb").read()).hexdigest()
result = SimulationResult.load(source)
size = os.path.getsize(source)
limits = list(range(size - 4096, size - 16, 64)) + [size // 2, 1000]
for limit in limits:
    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    try:
        result.save(target, overwrite=True)
    except OSError as exc:
        text = str(exc)
    else:
        sys.exit(f"limit {limit}: saved past the limit")
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (resource.RLIM_INFINITY,) * 2)
    if "\\n" in text or ".tmp" in text:
        sys.exit(f"limit {limit}: {text!r}")
    if hashlib.sha256(open(target, "rb").read()).hexdigest() != old:
        sys.exit(f"limit {limit}: the old file changed")
    left = [n for n in os.listdir(os.path.dirname(target)) if n.endswith(".tmp")]
    if left:
        sys.exit(f"limit {limit}: left {left}")
print(len(limits), "limits refused")
"""


@pytest.fixture(scope="module")
def run():
    return simulate(small(), 0.02, seed=3, progress=False)


def test_saved_bytes_round_trip(run, tmp_path):
    path = run.save(tmp_path / "run.h5")
    with h5py.File(path, "r") as f:  # the file h5py reads back holds the arrays saved
        np.testing.assert_array_equal(f["times"][()], run.times)
        np.testing.assert_array_equal(f["residual_variance"][()], run.residual_variance)
        for name, log in run.logs.items():
            assert f["logs"][name]["coefficients"][()].tobytes() == log.coeffs.tobytes()
    back = SimulationResult.load(path)  # and its recorded checksums verify
    assert back == run
    assert sorted(os.listdir(tmp_path)) == ["run.h5"]


@pytest.mark.parametrize("where", ["memory", "disk"])
def test_file_size_limit_mid_write_is_one_error(where, run, tmp_path):
    source = run.save(tmp_path / "source.h5")
    folder = tmp_path / "out"
    folder.mkdir()
    target = folder / "run.h5"
    target.write_bytes(b"the old file")  # replaced only by a whole new one
    old = hashlib.sha256(target.read_bytes()).hexdigest()
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[2])}
    child = subprocess.run([sys.executable, "-c", _CHILD, str(source), str(target), where],
                           capture_output=True, text=True, env=env, timeout=120)
    assert child.returncode == 0, (child.returncode, child.stdout, child.stderr[-2000:])
    assert child.stdout.strip().endswith("limits refused")
    assert hashlib.sha256(target.read_bytes()).hexdigest() == old
    assert os.listdir(folder) == ["run.h5"]
