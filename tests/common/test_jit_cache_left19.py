"""numba's cache as a best effort: a folder it cannot write compiles the kernel without it.

Reference: POSIX permission rules as the kernel applies them -- under ``umask 777`` the
``__pycache__`` folder numba creates beside a source file (and the user cache folder) has
mode 000, in which its owner without ``CAP_DAC_OVERRIDE`` can create no file, so numba
finds "no locator available" for ``cache=True``; and the same kernel compiled with its
cache written under umask 022 (numba's index file seen in ``__pycache__``), whose result
the umask-777 run must give bit for bit, plus numpy's value of the same sum.
Leftovers 18-forms (left): before, the first decorated kernel raised numba's
``RuntimeError`` traceback. The run is root under ``setpriv --bounding-set=-all
--inh-caps=-all`` (as tests/cli/test_permissions_left18.py); skipped, with the reason,
where the capabilities cannot be dropped.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from ..cli.test_permissions_left18 import nocap  # noqa: F401  (the fixture)

KERNEL = '''
from modalinfo.common.jit import jit


@jit
def weighted(x):
    s = 0.0
    for i in range(x.size):
        s += x[i] * (i + 0.5)
    return s


@jit(nogil=True)
def double(x):
    return 2.0 * x
'''

DRIVER = '''
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
import kern
x = np.random.default_rng(7).standard_normal(101)
print(kern.weighted(x).hex(), kern.double(0.3).hex())
'''


def _run(prefix, folder: Path, home: Path, umask: int):
    folder.mkdir()
    (folder / "kern.py").write_text(KERNEL, encoding="utf-8")
    (folder / "drive.py").write_text(DRIVER, encoding="utf-8")
    home.mkdir(exist_ok=True)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path), "HOME": str(home),
           "XDG_CACHE_HOME": str(home / ".cache")}
    env.pop("NUMBA_CACHE_DIR", None)
    return subprocess.run([*prefix, sys.executable, str(folder / "drive.py"), str(folder)],
                          env=env, capture_output=True, text=True, timeout=300,
                          preexec_fn=lambda: os.umask(umask))


def test_kernel_compiles_without_a_writable_cache(nocap, tmp_path):  # noqa: F811
    ok = _run([], tmp_path / "a", tmp_path / "home_a", 0o022)
    assert ok.returncode == 0 and ok.stderr == "", ok.stderr
    assert list((tmp_path / "a" / "__pycache__").glob("kern.weighted*.nbi"))  # cached

    run = _run(nocap, tmp_path / "b", tmp_path / "home_b", 0o777)
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr
    # one warning for the two kernels, naming the way out
    assert run.stderr.count("RuntimeWarning") == 1, run.stderr
    assert "NUMBA_CACHE_DIR" in run.stderr
    assert run.stdout == ok.stdout  # bit for bit the cached kernels' results
    x = np.random.default_rng(7).standard_normal(101)
    weighted, double = (float.fromhex(v) for v in run.stdout.split())
    assert weighted == pytest.approx(float(np.sum(x * (np.arange(101) + 0.5))), rel=1e-12)
    assert double == 0.6
