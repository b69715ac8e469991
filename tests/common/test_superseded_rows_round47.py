"""Rows of a batch folder's logs and analyses written under other keys are counted.

Round 47 PART b V09 / W09 (left by the round, closed here): a batch folder of 351d5180 /
4c25775f resumed by today's code ran its 4 tasks again (keys carry the source fingerprint,
round 15 PART b) and said "0 already done"; its summary now adds how many earlier rows of
the same (sha256, analysis, window) were not reused. Reference: the row files written here by
hand (their keys and identities), counted by eye: 2 of the same log and analysis under old
keys, 1 of another analysis, 1 unreadable file, 2 current rows.
"""

import json

from modalinfo.common.tasks.rows import superseded_rows

FIELDS = ("sha256", "analysis", "window")


def _row(key, analysis="summary", sha="a" * 64, **extra):
    return {"key": key, "sha256": sha, "analysis": analysis, **extra}


def test_counts_only_the_same_entries_under_other_keys(tmp_path):
    rows_dir = tmp_path / "rows"
    rows_dir.mkdir()
    now = [_row("k1"), _row("k2", sha="b" * 64)]
    files = [*now, _row("old1"), _row("old2", sha="b" * 64), _row("old3", analysis="forecast")]
    for r in files:
        (rows_dir / f"{r['key']}.json").write_text(json.dumps(r))
    (rows_dir / "broken.json").write_text("{not json")
    assert superseded_rows(rows_dir, now, FIELDS) == 2


def test_a_window_is_part_of_the_entry(tmp_path):
    rows_dir = tmp_path / "rows"
    rows_dir.mkdir()
    now = [_row("k1", window=0)]
    for r in [*now, _row("old", window=1), _row("old0", window=0)]:
        (rows_dir / f"{r['key']}.json").write_text(json.dumps(r))
    assert superseded_rows(rows_dir, now, FIELDS) == 1
    assert superseded_rows(tmp_path / "missing", now, FIELDS) == 0
