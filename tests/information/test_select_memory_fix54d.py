"""fix54-d (issue 27, round 53 PART b W07 / W08): the candidate search's memory.

``select`` on 3,000 modes x 10 lags peaked at 4.5 GB for a 48 MB log: about 10 arrays of
the candidates' size at once (the matrix, a centred copy and two temporaries of its
unit-norm copy, the residual copy, the FFT null's padded columns, spectra, product and
inverse transform, ``np.outer``'s update, a copy of the alive columns). The search now
holds the matrix, its unit-norm and residual copies and the spectra (2 arrays' worth,
complex), the rest in column blocks of 32 MiB; the estimate the refusal uses
(``search_bytes``: ``_WORKING_COPIES`` arrays and column blocks) follows.

Reference from outside the code: the operating system's account of the process's peak
resident memory (Linux's ``VmHWM`` of ``/proc/self/status``, reset to the resident size
by writing 5 to ``/proc/self/clear_refs`` just before the search, in a fresh subprocess:
the peak during the search less the resident size before it, everything imported, the
kernels compiled and the data made first; a compile's peak before the search once
hid it behind ``ru_maxrss``), in units of one candidate array (``8 x rows x columns`` bytes, numpy's
``nbytes`` of the lagged matrix). Deterministic: fixed seed, one process per
measurement; the allocator's page reuse moves the peak by a fraction of one array.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

DRIVER = r'''
import json, sys
import numpy as np
from modalinfo.information.selection import search_bytes, select_inputs

def status(key):  # kB -> bytes
    for line in open("/proc/self/status"):
        if line.startswith(key + ":"):
            return int(line.split()[1]) * 1024

T, M, L = 4000, 300, 10
x = np.random.default_rng(54).standard_normal((T, M))
select_inputs(x[:400, :5], 0, max_lag=2, n_surrogates=99, intervals=False, seed=0)  # warm
# the high-water mark reset to the resident size now: a numba compile or import before
# (hundreds of MB of LLVM) would otherwise hide the search's own peak
open("/proc/self/clear_refs", "w").write("5")
before = status("VmRSS")
res = select_inputs(x, 0, max_lag=L, n_surrogates=99, intervals=False, seed=0)
after = status("VmHWM")
one = 8 * (T - 1 - L + 1) * M * L
json.dump({"copies": (after - before) / one, "estimate": search_bytes(one // 8) / one,
           "n": len(res.inputs)}, sys.stdout)
'''


@pytest.mark.skipif(not Path("/proc/self/clear_refs").exists(), reason="Linux's clear_refs")
def test_search_peak_and_its_estimate():
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1",
               NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1")
    res = subprocess.run([sys.executable, "-c", DRIVER], capture_output=True, text=True,
                         env=env, timeout=900)
    assert res.returncode == 0, res.stderr[-2000:]
    got = json.loads(res.stdout)
    # 300 modes x 10 lags x 3,990 rows: one array 95.8 MB; before the fix about 9 of
    # them at once, now the matrix, two copies and the spectra (2) and blocks of 32 MiB
    assert got["copies"] <= 6.5, got
    # the refusal's estimate (in arrays) covers the peak, and not by more than twice
    assert got["copies"] <= got["estimate"] <= 2 * got["copies"], got
