"""``closedloop sweep`` counts one superseded run, and only runs of the same entry (review30).

Fixes 47-b's note "N earlier run(s) in ROWS of these (override, seed, predictor) were
not reused" (round 47 PART b V16, V23) was tested with two such runs, so a planted
``if stale > 1:`` (round 30 L1) passed, and with old runs differing in override and
seed only, so a planted ``("override", "seed")`` (L2: another predictor's run counted)
passed too. Reference: the row files written here by hand, counted by eye: one of the
same (override, seed, predictor) under another key, one of another predictor.
"""

import json
import types

import closedloop.sweep
from closedloop.cli import main


def _row(key, predictor="none"):
    return {"key": key, "override": "gain 0.3", "seed": 0, "predictor": predictor,
            "status": "ok", "strehl_peak_mean": 0.4, "corrected_fov_diameter_arcmin": 0.7}


def test_one_run_of_the_entry_is_counted_and_not_another_predictors(tmp_path, monkeypatch,
                                                                     capsys):
    out = tmp_path / "sdir"
    (out / "rows").mkdir(parents=True)
    now = [_row("a" * 64)]
    for r in [*now, _row("c" * 64), _row("d" * 64, predictor="oracle")]:
        (out / "rows" / f"{r['key']}.json").write_text(json.dumps(r))
    report = types.SimpleNamespace(n_specs=1, n_skipped=0, n_ok=1, n_error=0, n_lost=0)
    monkeypatch.setattr(closedloop.sweep, "sweep", lambda *a, **k: (now, report))
    grid = tmp_path / "grid.toml"
    grid.write_text('preset = "table1"\nduration = 0.02\nseeds = [0]\n')
    assert main(["sweep", str(grid), "--out", str(out), "--quiet"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[1].startswith(f"  1 earlier run(s) in {out / 'rows'} of these"), lines
