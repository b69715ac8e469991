"""Round 50 PART b of issue 27: the data-segment limit (``ulimit -d``) is a memory limit.

docs/ADVERSARIAL.md, "Round 50 PART b, issue 27", rows R01, R03-R05, R07: under
``ulimit -d`` (RLIMIT_DATA) the guard rails compared their estimates with the machine's
available memory only (21 GiB here): ``closedloop run --preset est-mcao`` (estimate 6.36
GiB) under 2.9 GiB built for 18 s of CPU before numpy's MemoryError, and ``modalinfo
info`` of a 430 kB log ran out of memory with "use a smaller log or smaller options".

References: Linux getrlimit(2) (since 4.7 RLIMIT_DATA bounds the data segment and the
private writable mappings, the ``VmData`` of proc(5)); the limit each test states
(``resource.setrlimit`` in a child, or ``monkeypatch`` of the reading, as the RLIMIT_AS
tests of round 27 do), ``VmData`` read by the test itself from ``/proc/self/status``.
"""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

resource = pytest.importorskip("resource")


def test_usable_memory_is_capped_by_the_data_limit_left():
    # a child sets RLIMIT_DATA to its VmData + 64 MiB and reads the guard rails' figures
    code = textwrap.dedent("""
        import resource
        def vmdata():
            for line in open("/proc/self/status"):
                if line.startswith("VmData:"):
                    return float(line.split()[1]) * 1024
        from modalinfo.common import memory
        room = 64 * 2**20
        limit = int(vmdata() + room)
        resource.setrlimit(resource.RLIMIT_DATA, (limit, resource.RLIM_INFINITY))
        print(memory.usable_memory_bytes(), memory.free_memory_bytes(), limit - vmdata())
        """)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr
    usable, free, left = (float(v) for v in proc.stdout.split())
    # at most the room the test left (VmData can only have grown since it was read)
    assert usable <= left + 1 and free <= left + 1
    assert usable > 0.5 * left  # and not zero: the limit less VmData, not the limit itself


def test_out_of_memory_line_names_the_data_limit(monkeypatch):
    import argparse

    from modalinfo.common import cli

    monkeypatch.setattr("modalinfo.common.memory.data_limit_bytes", lambda: 200 * 2**20)
    monkeypatch.setattr("modalinfo.common.memory.address_space_limit_bytes",
                        lambda: float("inf"))
    advice = cli._memory_advice(argparse.Namespace())
    assert "ulimit -d" in advice and "RLIMIT_DATA" in advice and "200.00 MiB" in advice
    assert "RLIMIT_AS" not in advice


def test_run_above_the_data_limit_is_refused_before_work(monkeypatch):
    from closedloop import presets
    from closedloop.resources import ResourceError, check_resources, estimate

    config = presets.est_mcao()
    need = estimate(config, 0.01).peak_bytes
    monkeypatch.setattr("modalinfo.common.memory.data_limit_bytes", lambda: need / 2)
    monkeypatch.setattr("modalinfo.common.memory.data_left_bytes", lambda: need / 2)
    with pytest.raises(ResourceError, match=r"ulimit -d, RLIMIT_DATA"):
        check_resources(config, 0.01, limit=2 * need)


def test_run_within_the_data_limit_passes(monkeypatch):
    from closedloop import presets
    from closedloop.resources import check_resources, estimate

    config = presets.kaos()
    need = estimate(config, 0.01).peak_bytes
    # a data limit below the resident estimate (whose baseline is mostly code) but with
    # room for what the run adds: R06 ran kaos under `ulimit -d 300000` (293 MiB)
    monkeypatch.setattr("modalinfo.common.memory.data_limit_bytes", lambda: 0.9 * need)
    monkeypatch.setattr("modalinfo.common.memory.data_left_bytes", lambda: need)
    assert check_resources(config, 0.01, limit=4 * need).peak_bytes == need


def test_est_mcao_under_a_real_data_limit_is_refused_in_one_line(tmp_path):
    limit = 3_000_000 * 1024  # R05: ulimit -d 3000000

    def cap():
        resource.setrlimit(resource.RLIMIT_DATA, (limit, limit))

    proc = subprocess.run(
        [sys.executable, "-m", "closedloop", "run", "--preset", "est-mcao", "--duration",
         "0.01", "--quiet"], capture_output=True, text=True, timeout=600, cwd=tmp_path,
        preexec_fn=cap)
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "RLIMIT_DATA" in lines[0], proc.stderr
    assert "--memory-limit raises" not in lines[0]


def test_a_lost_row_names_the_memory_limit_its_workers_inherit(monkeypatch):
    # R09 / R13: under `ulimit -d 300000` batch's and sweep's local workers died in
    # OpenBLAS's allocation four times; the row and the line said "run again to retry"
    from modalinfo.common.tasks.runner import lost_note

    monkeypatch.setattr("modalinfo.common.memory.address_space_limit_bytes",
                        lambda: float("inf"))
    monkeypatch.setattr("modalinfo.common.memory.data_limit_bytes", lambda: 300_000 * 1024)
    note = lost_note()
    assert "ulimit -d, RLIMIT_DATA) is 292.97 MiB" in note and "raise it first" in note
    monkeypatch.setattr("modalinfo.common.memory.data_limit_bytes", lambda: float("inf"))
    assert lost_note() == ""  # without a limit the row is Dask's message alone
