"""Round 50 PART b of issue 27: paper_figures names the process limit that stopped it.

docs/ADVERSARIAL.md, "Round 50 PART b, issue 27", rows R85 and R88:
``ulimit -f 100; python -m paper_figures --only 2 --quick`` ended with "OSError: File too
large" and ``ulimit -d 300000`` with "MemoryError: Unable to allocate 11.4 MiB ...",
naming neither limit, while modalinfo's and closedloop's lines name them.

Reference: the limits each test sets (``monkeypatch`` of the readings of
``resource.getrlimit``, as the RLIMIT_AS tests of round 27 do); EFBIG is errno 27 (Linux
``errno.h``).
"""

from __future__ import annotations

import errno

from paper_figures import __main__ as pf


def test_a_write_past_the_file_size_limit_names_it(monkeypatch, tmp_path, capsys):
    def run(args):
        raise OSError(errno.EFBIG, "File too large")

    monkeypatch.setattr(pf, "_run", run)
    monkeypatch.setattr("modalinfo.common.files.file_size_limit_bytes", lambda: 100 * 1024)
    out = tmp_path / "o"
    assert pf.main(["--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "File too large (the file-size limit (ulimit -f, RLIMIT_FSIZE) is 100.00" in err[0]
    assert err[0].endswith(f"'{out}' is as it was")


def test_a_lack_of_memory_names_the_data_limit(monkeypatch, tmp_path, capsys):
    def run(args):
        raise MemoryError("Unable to allocate 11.4 MiB for an array")

    monkeypatch.setattr(pf, "_run", run)
    monkeypatch.setattr("modalinfo.common.memory.data_limit_bytes", lambda: 300_000 * 1024)
    monkeypatch.setattr("modalinfo.common.memory.address_space_limit_bytes",
                        lambda: float("inf"))
    assert pf.main(["--out", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err
    assert "(the data-segment limit (ulimit -d, RLIMIT_DATA) is 292.97 MiB: raise it)" in err
