"""fix54-d (issue 27, round 53 PART b W39): Ctrl-C during a long Zernike matrix / Gram.

``fitting-error --plot`` on a 3,000-mode log stopped 12.6 s after SIGINT: Python raises
``KeyboardInterrupt`` only between bytecodes, and the Zernike matrix (one numba call) and
its Gram (one BLAS call) ran for seconds each. They run in chunks now
(``modalinfo.common.chunked``).

References from outside the code: numpy's ``a @ b`` / ``a.T @ a`` (the chunked products
equal them), the unchunked numba kernel's matrix (the chunked one equals it bit for bit),
and the operating system's signal: a ``kill -INT`` sent by another process while the
kernel runs, the process's exit status and the files on disk. No time is asserted: the
work done after the signal is counted (kernel calls and the pixels they computed),
whatever the machine's speed; the latency is in docs/ADVERSARIAL.md's benchmark note.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from modalinfo.bases import _kernels
from modalinfo.bases.indexing import noll_to_zernike
from modalinfo.bases.zernike import zernike_matrix
from modalinfo.common import chunked

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("shape", [(7, 5, 3), (5000, 300, 40), (20000, 400, 1)])
def test_matmul_equals_numpy(shape, monkeypatch):
    monkeypatch.setattr(chunked, "PRODUCT_TERMS", 1 << 16)  # many chunks
    n, k, m = shape
    rng = np.random.default_rng(1)
    a, b = rng.standard_normal((n, k)), rng.standard_normal((k, m))
    got = chunked.matmul(a, b)
    assert np.array_equal(got, a @ b) or np.allclose(got, a @ b, rtol=1e-13, atol=1e-12)


def test_matmul_rows_are_whole_blocks():
    """Defaults kept in one chunk below PRODUCT_TERMS: the very values of numpy."""
    rng = np.random.default_rng(2)
    a, b = rng.standard_normal((300, 40)), rng.standard_normal((40, 30))
    assert np.array_equal(chunked.matmul(a, b), a @ b)


@pytest.mark.parametrize("chunks", [1, 7])
def test_gram_equals_numpy(chunks):
    rng = np.random.default_rng(3)
    a = rng.standard_normal((700, 50))
    budget = (700 // chunks + 1) * 50 * 50
    old = chunked.PRODUCT_TERMS
    chunked.PRODUCT_TERMS = budget
    try:
        got = chunked.gram(a)
    finally:
        chunked.PRODUCT_TERMS = old
    ref = a.T @ a
    if chunks == 1:
        assert np.array_equal(got, ref)
    else:  # another order of the same terms: rounding (|G| ~ 700, eps 2.2e-16)
        np.testing.assert_allclose(got, ref, rtol=0, atol=700 * 50 * 2.2e-16)


def test_chunked_zernike_matrix_is_the_kernel_bit_for_bit():
    rng = np.random.default_rng(4)
    rho, theta = rng.uniform(0, 1, 5000), rng.uniform(-np.pi, np.pi, 5000)
    modes = np.arange(1, 400)
    n, m = noll_to_zernike(modes)
    ref = np.empty((5000, modes.size))
    _kernels.zernike_matrix(rho, theta, np.ascontiguousarray(n), np.ascontiguousarray(m), ref)
    assert np.array_equal(zernike_matrix(modes, rho, theta), ref)


#: fitting-error in-process, the Zernike kernel wrapped: its second call starts a separate
#: ``sh`` that sends SIGINT to this process 0.3 s later (while the kernel runs: one call
#: over every pixel takes seconds); each call's pixels and end time (None: never
#: returned to Python) are recorded.
DRIVER = r'''
import json, os, subprocess, sys, time
import modalinfo.bases._kernels as k
real, calls, sent = k.zernike_matrix, [], []
def wrapped(rho, theta, n, m, out):
    if len(calls) == 1 and not sent:  # the first call may compile (numba's callbacks
        sent.append(1)                  # swallow a KeyboardInterrupt: not this test's)
        subprocess.Popen(["sh", "-c", "sleep 0.3; date +%s.%N > " + sys.argv[2]
                          + "; kill -INT " + str(os.getpid())])
    calls.append([rho.shape[0], None])  # recorded before: the signal may end the call
    real(rho, theta, n, m, out)
    calls[-1][1] = time.time()
k.zernike_matrix = wrapped
from modalinfo.cli import main
try:
    rc = main(["fitting-error", sys.argv[1], "--orderings", "zernike:standard",
               "--pupil-pixels", "160", "--plot", sys.argv[3]])
finally:
    json.dump(calls, open(sys.argv[4], "w"))
sys.exit(rc)
'''


@pytest.mark.skipif(os.name != "posix", reason="kill -INT")
def test_sigint_during_the_zernike_matrix_stops_within_a_chunk(tmp_path):
    from modalinfo.io import save
    from modalinfo.telemetry import ModalLog

    n_modes = 3000  # Z2..Z3001 on a 160-pixel pupil: 20,096 pixels x 3,000 modes
    x = np.random.default_rng(5).standard_normal((200, n_modes)) * 0.01
    log = save(ModalLog(x, rate=1000.0, modes=list(range(2, n_modes + 2))), tmp_path / "wide.npz")
    png, stamp, calls = tmp_path / "fe.png", tmp_path / "stamp", tmp_path / "calls.json"
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1",
               NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
    res = subprocess.run([sys.executable, "-c", DRIVER, str(log), str(stamp), str(png),
                          str(calls)], capture_output=True, text=True, env=env, timeout=900)
    assert res.returncode == 130, res.stderr[-2000:]
    assert res.stderr.strip().splitlines()[-1].endswith("interrupted")
    assert "Traceback" not in res.stderr
    assert not png.exists() and not list(tmp_path.glob(".*fe.png*"))
    sent_at = float(stamp.read_text())
    done = json.loads(calls.read_text())
    after = [p for p, end in done if end is None or end > sent_at]
    # the call in progress when the signal came ends, no later call starts: at most one
    # chunk of pixels (1 Mi values / 3,000 modes = 349); unchunked, that one call
    # computed all 20,096 pixels after the signal
    assert len(after) <= 1
    assert sum(after) <= 1000
