r"""A stdout that cannot encode a label, and the user's own error handler (round 45 PART b).

E02 / E04 / E05 / E13 / E15 / E19 / E20 / E26 / E27 / E30: under ``PYTHONIOENCODING=ascii``
a label ``Tip_é`` or an output named ``e27_é.npz`` raised ``UnicodeEncodeError`` (a
ValueError) on stdout, reported as an input error, "'ascii' codec can't encode character
'\xe9' ...", exit 2, after complete files were written. Now: one line naming standard
output, its encoding and PYTHONIOENCODING=utf-8, exit 1, as for a stdout that refuses a
write. A ``UnicodeEncodeError`` raised anywhere else (reading the input) stays an input
error (exit 2): told apart by where it is raised, not by its type.

E17 / E22: ``PYTHONIOENCODING=ascii:replace`` / ``ascii:backslashreplace`` were replaced by
the command lines' own handler, and the commands failed as above; now the user's handler
writes what the encoding cannot hold, and a file name's undecodable byte still reads
``\xNN``.

References, outside the package: Python's codecs (``"Tip_é".encode("ascii", "replace")``
and ``"backslashreplace"``), ``codecs.escape_decode`` of the shown byte, numpy reading back
the file the command wrote, and the README's exit statuses (1: the run failed
after it started; 2: an input error before any work).
"""

from __future__ import annotations

import argparse
import codecs
import io
import os
import subprocess
import sys
from pathlib import Path

import pytest

from modalinfo.common.cli import dispatch

ROOT = Path(__file__).resolve().parents[2]
LABEL = "Tip_\u00e9"
BAD = os.fsdecode(b"bad\xff.npz")  # a file name that is not UTF-8 (PEP 383 surrogate)


def _parser(run) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="prog")
    sub = parser.add_subparsers(dest="command")
    sub.add_parser("go").set_defaults(_run=run)
    return parser


def _stdout(monkeypatch, errors: str) -> io.BytesIO:
    raw = io.BytesIO()
    monkeypatch.setattr(sys, "stdout", io.TextIOWrapper(raw, encoding="ascii", errors=errors,
                                                        write_through=True))
    return raw


def test_stdout_that_cannot_encode_is_a_failure_after_the_files(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("PYTHONIOENCODING", "ascii")
    raw = _stdout(monkeypatch, "strict")
    written = tmp_path / "out.bin"

    def run(args):
        from modalinfo.common.files import atomic_write

        # the commands' one writer (fixes 47-b: the line names files only if one was written)
        atomic_write(written, lambda fh: fh.write(b"complete"), overwrite=False)
        sys.stdout.write("wrote out.bin\n")
        sys.stdout.write(f"modes {LABEL}\n")
        return 0

    assert dispatch(_parser(run), ["go"], "prog") == 1  # was 2, an input error
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith("prog go: error: could not write standard output: its encoding "
                          "ascii (from PYTHONIOENCODING) cannot encode"), err
    assert "U+00E9" in err and "PYTHONIOENCODING=utf-8" in err
    assert "the files written before it are complete" in err
    assert raw.getvalue() == b"wrote out.bin\n" and written.read_bytes() == b"complete"


def test_an_encode_error_of_the_input_stays_an_input_error(monkeypatch, capsys):
    _stdout(monkeypatch, "strict")

    def run(args):
        LABEL.encode("ascii")  # raised while reading, not by a write to stdout

    assert dispatch(_parser(run), ["go"], "prog") == 2
    err = capsys.readouterr().err
    assert err.startswith("prog go: error: 'ascii' codec can't encode"), err
    assert "standard output" not in err


@pytest.mark.parametrize("errors", ["replace", "backslashreplace", "xmlcharrefreplace"])
def test_the_users_error_handler_is_kept(monkeypatch, capsys, errors):
    raw = _stdout(monkeypatch, errors)

    def run(args):
        sys.stdout.write(f"modes {LABEL}\nfile {BAD}\n")
        return 0

    assert dispatch(_parser(run), ["go"], "prog") == 0  # was 2
    expected = b"modes " + LABEL.encode("ascii", errors) + b"\nfile bad\\xff.npz\n"
    assert raw.getvalue() == expected
    assert codecs.escape_decode(b"bad\\xff.npz")[0] == os.fsencode(BAD)
    assert sys.stdout.errors == errors  # restored after the command
    assert capsys.readouterr().err == ""


def test_stderr_escapes_what_its_encoding_cannot_hold(monkeypatch):
    raw = io.BytesIO()
    monkeypatch.setattr(sys, "stderr", io.TextIOWrapper(raw, encoding="ascii",
                                                        errors="strict", write_through=True))

    def run(args):
        raise ValueError(f"no mode {LABEL} in {BAD}")

    assert dispatch(_parser(run), ["go"], "prog") == 2
    assert raw.getvalue() == b"prog go: error: no mode Tip_\\xe9 in bad\\xff.npz\n"


@pytest.mark.slow
def test_synth_under_ascii_writes_the_file_and_exits_1(tmp_path):
    """E27: ``PYTHONIOENCODING=ascii modalinfo synth e27_é.npz`` (exit 2 before)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1",
           "PYTHONIOENCODING": "ascii", "LC_ALL": "C.UTF-8"}
    name = "e27_\u00e9.npz"
    proc = subprocess.run([sys.executable, "-m", "modalinfo", "synth", name, "--frames",
                           "200"], cwd=tmp_path, env=env, capture_output=True, timeout=300,
                          check=False)
    err = proc.stderr.decode("ascii")
    assert proc.returncode == 1, err
    assert err.splitlines()[-1].startswith("modalinfo synth: error: could not write standard "
                                           "output: its encoding ascii"), err
    assert "Traceback" not in err
    import numpy as np

    with np.load(tmp_path / name) as npz:  # complete: numpy reads it back
        assert any(npz[k].shape[0] == 200 for k in npz.files)
