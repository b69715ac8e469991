"""fix55-a (issue 27): a Ctrl-C that lands while numba compiles a kernel is honoured.

numba compiles through LLVM, which calls llvmlite's object-cache callbacks (``ctypes``
callbacks); a SIGINT whose handler ran inside one was dropped by ``ctypes`` ("Exception
ignored on calling ctypes callback function ... KeyboardInterrupt") and the command ran
on to exit 0 with its figure written, or failed with numba's "RuntimeError: no compiled
object yet" (exit 1). ``modalinfo.common.startup.keep_interrupts`` has the dropped
signal delivered again.

References from outside the code: the operating system's signal (``os.kill`` of the
process's own SIGINT, so that Python's handler runs at the next bytecode, which is the
callback's: the race made deterministic), a real numba compile in a fresh
``NUMBA_CACHE_DIR``, libc's ``qsort`` calling a ``ctypes`` callback, the process's exit
status and the files on disk. No time is asserted.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from ._interrupts import callback_interrupted, child_env, compile_signalled

_env = child_env

#: The interrupt dropped in a ctypes callback, then Python code that must not run ("ran
#: on"): ``kept`` as the first argument installs the hook.
_CALLBACK_INTERRUPTED = (
    'if sys.argv[1] == "kept":\n    keep_interrupts()',
    'print("interrupted", type(exc).__name__, getattr(exc, "signum", None))\nsys.exit(130)')


@pytest.fixture(scope="module")
def small_log(tmp_path_factory) -> Path:
    """A 2,000-frame synthetic log (``modalinfo synth``), NPZ."""
    path = tmp_path_factory.mktemp("log") / "s.npz"
    subprocess.run([sys.executable, "-m", "modalinfo", "synth", str(path), "--frames", "2000",
                    "--seed", "3"], env=_env(), check=True, capture_output=True, timeout=600)
    return path


@pytest.mark.parametrize("at", [1, 3])
def test_ctrl_c_during_a_numba_compile_exits_130_without_the_figure(at, small_log, tmp_path):
    """Before the fix: exit 0 and the PNG written (at=1), or numba's RuntimeError (exit 1)."""
    cache = tmp_path / "numba-cache"
    cache.mkdir()  # empty: every kernel of the command is compiled in this run
    png = tmp_path / "fe.png"
    proc = subprocess.run(
        [sys.executable, "-c", compile_signalled("modalinfo"), "fitting-error",
         str(small_log), "--orderings", "zernike:standard", "--plot", str(png)],
        env=_env(NUMBA_CACHE_DIR=str(cache), AT=str(at)), cwd=tmp_path,
        capture_output=True, text=True, timeout=600)
    assert proc.returncode == 130, proc.stderr[-3000:]
    assert proc.stderr == "modalinfo: interrupted\n"  # one line: nothing "ignored"
    assert not png.exists()
    assert proc.stdout == ""  # the table is printed after the compiles: no partial output


def test_the_compile_signalled_still_runs_when_no_signal_comes(small_log, tmp_path):
    """Guard: the harness itself (AT never reached) leaves the command as it is: exit 0."""
    cache = tmp_path / "numba-cache"
    cache.mkdir()
    png = tmp_path / "fe.png"
    proc = subprocess.run(
        [sys.executable, "-c", compile_signalled("modalinfo"), "fitting-error",
         str(small_log), "--orderings", "zernike:standard", "--plot", str(png)],
        env=_env(NUMBA_CACHE_DIR=str(cache), AT="100000"), cwd=tmp_path,
        capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert png.exists()


@pytest.mark.parametrize(("raise_it", "expected"), [
    ("raise KeyboardInterrupt", "interrupted KeyboardInterrupt None"),
    ("os.kill(os.getpid(), signal.SIGINT)", "interrupted KeyboardInterrupt None"),
])
def test_an_interrupt_dropped_in_a_ctypes_callback_is_raised_after_it(raise_it, expected):
    """The mechanism: without the hook Python drops it and the code after the call runs."""
    setup, report = _CALLBACK_INTERRUPTED
    script = callback_interrupted(setup, raise_it, "KeyboardInterrupt", report)
    kept = subprocess.run([sys.executable, "-c", script, "kept"], env=_env(),
                          capture_output=True, text=True, timeout=120)
    assert (kept.returncode, kept.stdout.strip()) == (130, expected), kept.stderr
    assert "Exception ignored" not in kept.stderr
    # the reference: Python's own behaviour, the interrupt dropped and the code run on
    plain = subprocess.run([sys.executable, "-c", script, "plain"], env=_env(),
                           capture_output=True, text=True, timeout=120)
    assert (plain.returncode, plain.stdout.strip()) == (0, "ran on")
    assert "Exception ignored on calling ctypes callback" in plain.stderr


def test_a_signal_raised_as_an_interrupt_is_delivered_as_itself():
    """paper_figures raises SIGTERM as a KeyboardInterrupt with its ``signum``: SIGTERM again."""
    script = callback_interrupted("""
        keep_interrupts()
        class Terminated(KeyboardInterrupt):
            def __init__(self, signum):
                super().__init__(signum)
                self.signum = signum
        def handler(signum, frame):
            raise Terminated(signum)
        signal.signal(signal.SIGTERM, handler)
    """, "raise Terminated(signal.SIGTERM)", "Terminated", """
        print("terminated", exc.signum)
        sys.exit(143)
    """)
    proc = subprocess.run([sys.executable, "-c", script], env=_env(), capture_output=True,
                          text=True, timeout=120)
    assert (proc.returncode, proc.stdout.strip()) == (143, "terminated 15"), proc.stderr


def test_other_unraisable_exceptions_keep_pythons_report():
    """A dropped ValueError is still reported by Python's hook and the code runs on."""
    script = textwrap.dedent("""
        from modalinfo.common.startup import keep_interrupts
        keep_interrupts()
        class Noisy:
            def __del__(self):
                raise ValueError("from __del__")
        Noisy()
        print("ran on")
    """)
    proc = subprocess.run([sys.executable, "-c", script], env=_env(), capture_output=True,
                          text=True, timeout=120)
    assert (proc.returncode, proc.stdout.strip()) == (0, "ran on")
    assert "Exception ignored in" in proc.stderr and "from __del__" in proc.stderr
