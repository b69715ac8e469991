r"""Report lines on stdout show a user's path in the one shown form (fix49-c, item 1).

Stop 55 (fixes 48-a) quoted every path of a refusal through ``files.quoted``, but the
lines that *report* a path (``info``'s ``file  LOG``, ``convert`` / ``synth``'s ``wrote
OUT``, batch's ``table: ... -> CSV``, ``plot: PNG``) still printed it raw: a name holding
a newline split the line in two, an ANSI escape (ESC ``[31m``) recoloured the terminal,
and ``shown_name`` itself left both as they were. Reference: ``codecs.escape_decode`` of
the shown name gives back the name's bytes (``os.fsencode``), the line is one line, and
no byte below 0x20 but the newline reaches the terminal.
"""

from __future__ import annotations

import codecs
import os
import subprocess
import sys
from pathlib import Path

import pytest

from modalinfo.common.files import quoted, shown_name

from .conftest import batch_stand_in, exit_code, write_small_log

#: a newline, a tab, an ANSI colour escape, a C1 control and an undecodable byte
NAME = os.fsdecode(b"a\nb\tc\x1b[31m\xc2\x9bd\xe9.npz")
REPO = Path(__file__).resolve().parents[2]


def _bytes_of(shown: str) -> bytes:
    return codecs.escape_decode(shown.encode("utf-8"))[0]


@pytest.mark.parametrize("name", [NAME, "x\u2028y.npz", "a\\x1b.npz", "plain é.npz"])
def test_shown_name_escapes_controls_one_to_one(name):
    shown = shown_name(name)
    assert shown.isprintable(), shown
    assert len(shown.splitlines()) == 1
    assert _bytes_of(shown) == os.fsencode(name)
    assert quoted(name) == f"'{shown}'"


def test_an_error_line_keeps_the_whole_name(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert exit_code(["info", NAME]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "\x1b" not in err, err
    assert f"'{shown_name(NAME)}'" in err


def _one_line_naming(out: str, start: str, path) -> str:
    (line,) = [x for x in out.splitlines() if x.startswith(start)]
    assert "\x1b" not in out and "\t" not in out and "\x9b" not in out, out
    assert shown_name(path) in line, line
    return line


def test_info_convert_synth_report_the_shown_name(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert exit_code(["synth", NAME, "--frames", "200"]) == 0
    _one_line_naming(capsys.readouterr().out, "wrote ", NAME)
    assert exit_code(["info", NAME]) == 0
    line = _one_line_naming(capsys.readouterr().out, "file ", NAME)
    assert _bytes_of(line.split(None, 1)[1]) == os.fsencode(NAME)
    out_name = NAME.replace(".npz", ".csv")
    assert exit_code(["convert", NAME, out_name]) == 0
    line = _one_line_naming(capsys.readouterr().out, "wrote ", out_name)
    assert _bytes_of(line[len("wrote "):line.index(": ")]) == os.fsencode(out_name)


def test_batch_table_rows_and_plot_lines(tmp_path, monkeypatch, capsys):
    out = Path(os.fsdecode(os.path.join(os.fsencode(tmp_path), b"o\nu\x1b[1mt\xe9")))
    rows = [{"path": str(tmp_path / "log.npz"), "analysis": "summary", "status": "ok"}]
    result = batch_stand_in(rows, out, plots=[out / "plots" / "p.png"])
    monkeypatch.setattr("modalinfo.batch.analyse_archive", lambda *a, **k: result)
    os.makedirs(out / "rows")
    (out / "rows" / "old.json").write_text('{"sha256": "0", "analysis": "x", "window": 0}')
    assert exit_code(["batch", str(tmp_path), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    table = _one_line_naming(text, "table: ", out / "batch.csv")
    assert shown_name(out / "batch.parquet") in table
    _one_line_naming(text, "plot: ", out / "plots" / "p.png")


def test_stdout_ascii_and_c_locale_never_raise(tmp_path):
    """A subprocess under ``LANG=C`` and ``PYTHONIOENCODING=ascii``: no UnicodeEncodeError."""
    write_small_log(tmp_path / NAME, 50)
    env = {**os.environ, "LANG": "C", "LC_ALL": "C", "PYTHONIOENCODING": "ascii",
           "PYTHONPATH": str(REPO)}
    done = subprocess.run([sys.executable, "-m", "modalinfo", "info", NAME], cwd=tmp_path,
                          env=env, capture_output=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    (line,) = [x for x in done.stdout.split(b"\n") if x.startswith(b"file ")]
    assert line.split(None, 1)[1] == shown_name(NAME).encode("ascii")
    assert _bytes_of(line.split(None, 1)[1].decode("ascii")) == os.fsencode(NAME)



@pytest.mark.parametrize("argv", [["convert", "{log}", "o.x\ny"],
                                  ["fitting-error", "{log}", "--plot", "p.q\ty"]])
def test_a_refused_extension_is_quoted_whole(make_small_log, tmp_path, monkeypatch, capsys,
                                             argv):
    """The extension of a refused output was quoted raw (``'{path.suffix}'``)."""
    monkeypatch.chdir(tmp_path)
    log = str(make_small_log(50))
    assert exit_code([a.format(log=log) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.isascii() and "\x1b" not in err, err
    suffix = os.path.splitext(argv[2] if argv[0] == "convert" else argv[-1])[1]
    assert quoted(suffix) in err, err
