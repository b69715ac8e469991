"""A Ctrl-C or a SIGTERM while numba compiles ends ``python -m paper_figures`` (read56).

fix55-a (issue 27) had ``modalinfo.common.startup.keep_interrupts`` deliver again a
signal that Python dropped in a C callback (llvmlite's object-cache callback during a
numba compile), in ``python -m modalinfo`` and ``python -m closedloop`` only: measured
before this change, ``python -m paper_figures --only 1`` signalled at the first compile
printed "Exception ignored on calling ctypes callback function ... KeyboardInterrupt"
and ran on 252 s to exit 0 with its report written. And the hook delivers a
``KeyboardInterrupt`` subclass by its ``signum``, which paper_figures' ``_Terminated``
(its SIGTERM) did not carry: a SIGTERM came back as a SIGINT (130, "interrupted").

References from outside the code: the operating system's signals (``os.kill``), a real
numba compile in a fresh ``NUMBA_CACHE_DIR``, libc's ``qsort`` calling a ``ctypes``
callback (tests/common/_interrupts.py), the process's exit status (130 for SIGINT,
128 + 15 for SIGTERM, the shell's convention) and the output folder on disk. No time
is asserted.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from ..common._interrupts import callback_interrupted, child_env, compile_signalled


def test_paper_figures_sigterm_dropped_in_a_callback_comes_back_as_sigterm():
    """paper_figures' own handler and exception class: 143 "terminated", not 130."""
    script = callback_interrupted("""
        keep_interrupts()
        from paper_figures.__main__ import _Terminated, _terminated
        signal.signal(signal.SIGTERM, _terminated)
    """, "os.kill(os.getpid(), signal.SIGTERM)", "KeyboardInterrupt", """
        print(type(exc).__name__, getattr(exc, "code", None))
        sys.exit(getattr(exc, "code", 130))
    """)
    proc = subprocess.run([sys.executable, "-c", script], env=child_env(),
                          capture_output=True, text=True, timeout=300)
    assert (proc.returncode, proc.stdout.strip()) == (143, "_Terminated 143"), proc.stderr
    assert "Exception ignored" not in proc.stderr


@pytest.mark.parametrize(("sig", "code", "word"), [("SIGINT", 130, "interrupted"),
                                                   ("SIGTERM", 143, "terminated")])
def test_a_signal_during_a_numba_compile_ends_paper_figures(sig, code, word, tmp_path):
    """Before: the signal dropped, Figure 1 made, exit 0 and report.md written."""
    cache = tmp_path / "numba-cache"
    cache.mkdir()  # empty: the run's first kernel is compiled here, and signalled
    out = tmp_path / "out"
    proc = subprocess.run(
        [sys.executable, "-c", compile_signalled("paper_figures", "paper_figures"),
         "--only", "1", "--out", str(out)],
        env=child_env(NUMBA_CACHE_DIR=str(cache), AT="1", SIG=sig), cwd=tmp_path,
        capture_output=True, text=True, timeout=1200)
    assert proc.returncode == code, proc.stderr[-3000:]
    assert "Exception ignored" not in proc.stderr
    lines = proc.stderr.strip().splitlines()  # one line: "python -m paper_figures: ..."
    assert len(lines) == 1 and f"paper_figures: {word}; " in lines[0], proc.stderr
    assert lines[0].endswith("is as it was")
    assert not out.exists()  # as it was: the run made no folder
