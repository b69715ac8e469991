r"""Batch's superseded-rows line, its failed-rows warning, forecast's wrote line (review32).

Planted-bug review of fix49-c (round 32): fix49-c's batch test named an --out folder
holding a newline, ESC and the byte 0xE9, but wrote no superseded row and no error row,
so ``{rows_dir}`` raw in the "earlier row(s) in ROWS" line (R32-C3) and ``{csv_path}``
raw in stderr's "N of M rows failed; see CSV" (R32-C4) passed it. Reference: the
docstring of ``files.shown_name``: ``codecs.escape_decode`` of the shown form is the
path's bytes (``os.fsencode``), and every line is one printable line.
"""

from __future__ import annotations

import codecs
import json
import os
from pathlib import Path

import pytest

from modalinfo.cli import main
from modalinfo.common.files import quoted, shown_name

from .conftest import batch_stand_in, exit_code

SHA = "a" * 64


def _row(key, status="ok"):
    return {"key": key, "path": "in/x.npz", "sha256": SHA, "analysis": "summary",
            "window": 0, "status": status, "error_type": "ValueError",
            "error_message": "bad"}


def _out(tmp_path) -> Path:
    return Path(os.fsdecode(os.path.join(os.fsencode(tmp_path), b"o\nu\x1b[1mt\xe9")))


def _check_line(text: str, marker: str, path: Path) -> None:
    (line,) = [x for x in text.splitlines() if marker in x]
    assert line.isprintable(), line
    shown = shown_name(path)
    assert shown in line, line
    assert codecs.escape_decode(shown.encode("utf-8"))[0] == os.fsencode(path)


def test_superseded_rows_line_and_failed_rows_warning(tmp_path, monkeypatch, capsys):
    out = _out(tmp_path)
    rows_dir = out / "rows"
    rows_dir.mkdir(parents=True)
    now = [_row("k" * 64), _row("e" * 64, status="error")]
    for r in [*now, _row("o" * 64)]:
        (rows_dir / f"{r['key']}.json").write_text(json.dumps(r))
    result = batch_stand_in(now, out)
    monkeypatch.setattr("modalinfo.batch.analyse_archive", lambda *a, **k: result)
    (tmp_path / "in").mkdir()
    assert main(["batch", str(tmp_path / "in"), "--out", str(out)]) == 1
    captured = capsys.readouterr()
    assert "\x1b" not in captured.out and "\x1b" not in captured.err
    _check_line(captured.out, "not reused", rows_dir)
    _check_line(captured.err, "rows failed", out / "batch.csv")


def test_forecast_wrote_line_shows_the_out_folder(make_small_log, tmp_path, capsys):
    # R32-C5: forecast's "wrote forecast.json, ... to OUT" line printed OUT raw
    # (not the byte 0xE9: forecast.csv's provenance comment cannot hold it, review32's
    # finding, docs/MUTATION.md round 32)
    log = make_small_log(600)
    out = tmp_path / "o\nu\x1b[1mt\u00e9"
    assert main(["forecast", str(log), "--predictors", "linear", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "\x1b" not in text, text
    _check_line(text, "wrote forecast", out)


@pytest.mark.slow  # 37 s on the loaded 2-core machine (reorder's search, the figure)
def test_reorder_and_fitting_error_written_lines(make_small_log, tmp_path, capsys):
    # R32-C9 / C8: "ordering written to OUT" and "figure written to PLOT" printed raw
    log = make_small_log(300)
    out = tmp_path / "o\nr\x1b[1md\u00e9.json"
    assert main(["reorder", str(log), "--method", "mi_marginal", "--seed", "7", "--budget",
                 "2000", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "\x1b" not in text, text
    _check_line(text, "ordering written to", out)
    plot = tmp_path / "f\ni\x1b[1mg.png"
    assert main(["fitting-error", str(log), "--plot", str(plot)]) == 0
    text = capsys.readouterr().out
    assert "\x1b" not in text, text
    _check_line(text, "figure written to", plot)


def test_convert_names_every_extra_file_shown(make_small_log, tmp_path, capsys):
    # R32-C12: convert's "got N files (IN, OUT, MORE...)" listed the extra names raw
    log = make_small_log(50)
    extra = "c\x1b[1md\ne.npz"
    assert exit_code(["convert", log, tmp_path / "o.npz", extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "\x1b" not in err, err
    assert quoted(extra) in err, err


def test_what_file_suggests_a_command_that_pastes(tmp_path):
    # R32-C11: io.formats.what_file's `modalinfo info PATH` used quoted()'s reading form;
    # reference: shlex.split of the suggested command gives the path back
    import re
    import shlex

    from modalinfo.io.formats import what_file

    from .conftest import write_small_log

    path = write_small_log(tmp_path / "it's a.npz", 50)
    hint = what_file(path)
    (command,) = re.findall(r"`(modalinfo info [^`]*)`", hint)
    assert shlex.split(command)[2] == str(path), hint
