"""``modalinfo batch``'s summary counts the earlier rows it did not reuse (review30, round 30 B1).

Round 47 PART b V09 / W09 (fixes 47-b) added the line "N earlier row(s) in ROWS of these logs
and analyses were not reused" to the batch summary; its helper ``superseded_rows`` is tested
alone, the line was not: a planted ``if stale > 1:`` (one superseded row said nothing) passed
every test. ``analyse_archive`` is replaced by a stand-in result, so the line is judged
alone. Reference: the row files written here by hand, counted by eye: one of the same log,
analysis and window under another key, one of another window (not counted).
"""

from __future__ import annotations

import json

from modalinfo.cli import main

from .conftest import batch_stand_in

SHA = "a" * 64


def _row(key, window=0):
    return {"key": key, "path": "in/x.npz", "sha256": SHA, "analysis": "summary",
            "window": window, "status": "ok"}


def _run(tmp_path, monkeypatch, rows) -> str:
    result = batch_stand_in(rows, tmp_path / "out")
    monkeypatch.setattr("modalinfo.batch.analyse_archive", lambda *a, **k: result)
    (tmp_path / "in").mkdir(exist_ok=True)
    assert main(["batch", str(tmp_path / "in"), "--out", str(tmp_path / "out")]) == 0
    return result


def test_one_superseded_row_is_counted(tmp_path, monkeypatch, capsys):
    rows_dir = tmp_path / "out" / "rows"
    rows_dir.mkdir(parents=True)
    now = [_row("k" * 64)]
    for r in [*now, _row("o" * 64), _row("w" * 64, window=1)]:
        (rows_dir / f"{r['key']}.json").write_text(json.dumps(r))
    _run(tmp_path, monkeypatch, now)
    out = capsys.readouterr().out
    lines = [x for x in out.splitlines() if "not reused" in x]
    assert lines == [f"1 earlier row(s) in {rows_dir} of these logs and analyses were not "
                     "reused: another version of the code or other settings wrote them "
                     "(kept there, not in the table)"], out


def test_no_superseded_row_no_line(tmp_path, monkeypatch, capsys):
    rows_dir = tmp_path / "out" / "rows"
    rows_dir.mkdir(parents=True)
    now = [_row("k" * 64)]
    (rows_dir / f"{now[0]['key']}.json").write_text(json.dumps(now[0]))
    _run(tmp_path, monkeypatch, now)
    assert "not reused" not in capsys.readouterr().out
