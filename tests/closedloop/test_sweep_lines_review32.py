r"""``closedloop sweep``'s table and superseded-runs lines show the folder's shown name (review32).

Planted-bug review of fix49-c (round 32): the sweep's "table OUT/sweep.csv" line
(R32-C7) could print the --out folder raw (a newline splitting the line, ESC reaching
the terminal) and pass every test: the stubbed sweep of ``conftest.stubbed_sweep`` names
a plain folder. Reference: ``files.shown_name``'s docstring (``codecs.escape_decode`` of
the shown form is the path's bytes) and one printable line per report line.
"""

import codecs
import json
import os
import types

from closedloop.cli import main
from modalinfo.common.files import shown_name

from .conftest import sweep_row


def test_table_and_superseded_lines_name_the_folder_shown(tmp_path, monkeypatch, capsys):
    import closedloop.sweep

    out = tmp_path / "s\nd\x1b[1mi\u00e9r"
    (out / "rows").mkdir(parents=True)
    now = [sweep_row("a" * 64)]
    for r in [*now, sweep_row("c" * 64)]:
        (out / "rows" / f"{r['key']}.json").write_text(json.dumps(r))
    report = types.SimpleNamespace(n_specs=1, n_skipped=0, n_ok=1, n_error=0, n_lost=0)
    monkeypatch.setattr(closedloop.sweep, "sweep", lambda *a, **k: (now, report))
    grid = tmp_path / "grid.toml"
    seeds = sorted({int(r["seed"]) for r in now})
    grid.write_text(f'preset = "table1"\nduration = 0.02\nseeds = {seeds}\n')
    assert main(["sweep", str(grid), "--out", str(out), "--quiet"]) == 0
    text = capsys.readouterr().out
    assert "\x1b" not in text, text
    for marker, path in (("; table ", out / "sweep.csv"), ("earlier run(s) in", out / "rows")):
        (line,) = [x for x in text.splitlines() if marker in x]
        assert line.isprintable() and shown_name(path) in line, line
        assert codecs.escape_decode(shown_name(path).encode("utf-8"))[0] == os.fsencode(path)
