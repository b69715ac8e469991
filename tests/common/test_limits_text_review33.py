"""Round 50 PART b's process-limit helpers against their docstrings (review33).

Mutation round 33 (docs/MUTATION.md): plants in ``files.terminating_signals``,
``files._program``, ``files.pid_alive``, ``memory._soft_limit``,
``memory.memory_limits_text`` and ``cli._memory_advice`` that the round-50 files let
through. References: POSIX.1-2017 signal.h (SIGVTALRM, SIGPROF and SIGXCPU end a process
by default); ``kill(2)`` (pid 0 is the caller's process group, not a process; a pid
below 1 names no process); ``getrlimit(2)`` (a soft value of RLIM_INFINITY: no limit);
the docstrings' own examples of the texts.
"""

from __future__ import annotations

import argparse
import math
import signal
import sys
from types import SimpleNamespace

import pytest

from modalinfo.common import cli, files, memory


@pytest.mark.skipif(not hasattr(signal, "SIGXCPU"), reason="POSIX only")
def test_the_timer_and_cpu_limit_signals_end_a_save():
    names = {signal.Signals(s).name for s in files.terminating_signals()}
    assert {"SIGVTALRM", "SIGPROF", "SIGXCPU", "SIGTERM"} <= names
    assert not names & {"SIGINT", "SIGPIPE", "SIGXFSZ", "SIGSEGV"}


@pytest.mark.parametrize(("spec", "expected"), [("closedloop.__main__", "closedloop"),
                                                ("modalinfo.__main__", "modalinfo"),
                                                ("paper_figures", "paper_figures")])
def test_the_program_is_named_as_typed(monkeypatch, spec, expected):
    monkeypatch.setitem(sys.modules, "__main__",
                        SimpleNamespace(__spec__=SimpleNamespace(name=spec)))
    assert files._program() == expected


def test_pid_zero_and_below_are_no_process():
    assert files.pid_alive(0) is False and files.pid_alive(-1) is False


def test_a_soft_limit_of_zero_or_infinity_is_no_limit(monkeypatch):
    resource = pytest.importorskip("resource")
    for soft in (resource.RLIM_INFINITY, 0):
        monkeypatch.setattr(resource, "getrlimit", lambda _which, s=soft: (s, s))
        assert memory.data_limit_bytes() == math.inf
    monkeypatch.setattr(resource, "getrlimit", lambda _which: (3 * 2**30, 4 * 2**30))
    assert memory.data_limit_bytes() == 3 * 2**30


def test_both_limits_are_joined_by_and_and_advised_as_them(monkeypatch):
    monkeypatch.setattr(memory, "data_limit_bytes", lambda: 200 * 2**20)
    monkeypatch.setattr(memory, "address_space_limit_bytes", lambda: 2**30)
    text = memory.memory_limits_text()
    assert text == ("the address-space limit (ulimit -v, RLIMIT_AS) is 1.00 GiB and the "
                    "data-segment limit (ulimit -d, RLIMIT_DATA) is 200.00 MiB")
    assert cli._memory_advice(argparse.Namespace()).startswith(text + " for this process: "
                                                               "raise them, or use ")
    monkeypatch.setattr(memory, "address_space_limit_bytes", lambda: math.inf)
    assert ": raise it, or use " in cli._memory_advice(argparse.Namespace())


def test_a_file_too_large_line_names_the_limit_in_brackets(monkeypatch):
    import errno

    monkeypatch.setattr(files, "file_size_limit_text",
                        lambda: "the file-size limit (ulimit -f, RLIMIT_FSIZE) is 30.00 KiB")
    line = files.error_line(OSError(errno.EFBIG, "File too large"))
    assert line == ("[Errno 27] File too large (the file-size limit (ulimit -f, "
                    "RLIMIT_FSIZE) is 30.00 KiB)")


def test_the_data_room_is_the_limit_less_vmdata(monkeypatch):
    """``data_left_bytes`` = the soft limit less /proc/self/status's VmData (in kB)."""
    def vmdata():
        with open("/proc/self/status", encoding="ascii") as fh:
            return next(float(line.split()[1]) * 1024 for line in fh
                        if line.startswith("VmData:"))

    pytest.importorskip("resource")
    try:
        before = vmdata()
    except (OSError, StopIteration):
        pytest.skip("no /proc/self/status VmData")
    monkeypatch.setattr(memory, "data_limit_bytes", lambda: 2.0**45)
    left = memory.data_left_bytes()
    # VmData moves by a few pages between the reads: 1 % of it
    assert 2.0**45 - left == pytest.approx(before, rel=0.01)
