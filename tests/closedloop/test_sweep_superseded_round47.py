"""``closedloop sweep`` resumed in a folder whose runs another version of the code wrote says so.

Round 47 PART b V16, W16, V23: a sweep folder of 351d5180 / 4c25775f resumed by today's code
ran every entry again (task keys carry the source fingerprint, round 15 PART b) and printed
"2 runs: 0 already done, 2 ran" (V23: "4 runs: 0 already done, 4 ran" where 1 was finished)
without a word of the earlier runs set aside in rows/. Reference: the folder's own row files
(their key, override, seed and predictor) against the rows of this run; the sweep itself is
replaced by a stub returning those rows, so no simulation runs.
"""

import json
import types

import closedloop.sweep
from closedloop.cli import main


def _row(key, seed):
    return {"key": key, "override": "gain 0.3", "seed": seed, "predictor": "none",
            "status": "ok", "strehl_peak_mean": 0.4, "corrected_fov_diameter_arcmin": 0.7}


def test_runs_of_other_code_are_counted(tmp_path, monkeypatch, capsys):
    out = tmp_path / "sdir"
    (out / "rows").mkdir(parents=True)
    now = [_row("a" * 64, 0), _row("b" * 64, 1)]
    old = [_row("c" * 64, 0), _row("d" * 64, 1), {**_row("e" * 64, 2), "seed": 7,
                                                    "override": "other grid"}]
    for r in now + old:
        (out / "rows" / f"{r['key']}.json").write_text(json.dumps(r))
    report = types.SimpleNamespace(n_specs=2, n_skipped=0, n_ok=2, n_error=0, n_lost=0)
    monkeypatch.setattr(closedloop.sweep, "sweep", lambda *a, **k: (now, report))
    grid = tmp_path / "grid.toml"
    grid.write_text('preset = "table1"\nduration = 0.02\nseeds = [0, 1]\n')
    assert main(["sweep", str(grid), "--out", str(out), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("2 runs: 0 already done, 2 ran")
    # the two runs of the same entries under other keys; the other grid's row is not counted
    assert lines[1].startswith(f"  2 earlier run(s) in {out / 'rows'} of these")


def test_a_plain_resume_says_nothing_more(tmp_path, monkeypatch, capsys):
    out = tmp_path / "sdir"
    (out / "rows").mkdir(parents=True)
    now = [_row("a" * 64, 0)]
    (out / "rows" / f"{'a' * 64}.json").write_text(json.dumps(now[0]))
    report = types.SimpleNamespace(n_specs=1, n_skipped=1, n_ok=0, n_error=0, n_lost=0)
    monkeypatch.setattr(closedloop.sweep, "sweep", lambda *a, **k: (now, report))
    grid = tmp_path / "grid.toml"
    grid.write_text('preset = "table1"\nduration = 0.02\nseeds = [0]\n')
    assert main(["sweep", str(grid), "--out", str(out), "--quiet"]) == 0
    assert "earlier run" not in capsys.readouterr().out
