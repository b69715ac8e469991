"""``closedloop sweep`` counts one superseded run, and only runs of the same entry (review30).

Fixes 47-b's note "N earlier run(s) in ROWS of these (override, seed, predictor) were
not reused" (round 47 PART b V16, V23) was tested with two such runs, so a planted
``if stale > 1:`` (round 30 L1) passed, and with old runs differing in override and
seed only, so a planted ``("override", "seed")`` (L2: another predictor's run counted)
passed too. Reference: the row files written here by hand, counted by eye: one of the
same (override, seed, predictor) under another key, one of another predictor.
"""

from .conftest import sweep_row


def test_one_run_of_the_entry_is_counted_and_not_another_predictors(stubbed_sweep):
    now = [sweep_row("a" * 64)]
    rows, lines = stubbed_sweep([*now, sweep_row("c" * 64),
                                 sweep_row("d" * 64, predictor="oracle")], now)
    assert lines[1].startswith(f"  1 earlier run(s) in {rows} of these"), lines
