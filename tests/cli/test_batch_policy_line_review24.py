"""Planted-bug review 24 (issue 27): batch's "outlier policy applied" line.

Reference: rows written by hand as the batch writes its flagged rows (one per log and
analysis, with ``analysis``, ``path`` and the ``outliers`` policy that ran), counted
by hand: two logs flagged, ``summary`` run with drop (``--set summary.outliers=drop``)
and ``ordering`` with the default warn. Each analysis names its policy and the number
of distinct logs it applied it to (a log analysed twice is one log), and the hint that
clip, drop or raise act on the flagged values is given because one analysis warned.
"""

from __future__ import annotations

from modalinfo.cli.cmd_batch import _policies_applied


def _rows():
    return [{"analysis": a, "path": p, "outliers": pol, "status": "ok"}
            for p in ("n1/a.npz", "n2/b.npz")
            for a, pol in (("summary", "drop"), ("ordering", "warn"))]


def test_each_analysis_names_its_policy_and_its_logs():
    line = _policies_applied(_rows())
    assert line.startswith("outlier policy applied: ordering: warn on 2 log(s), "
                           "summary: drop on 2 log(s) (")
    assert "act on them" in line  # ordering warned: the hint goes with it


def test_one_log_under_two_analyses_counts_once_per_analysis():
    rows = [r for r in _rows() if r["path"] == "n1/a.npz"]
    rows.append(dict(rows[0]))  # a second row of the same log and analysis (a window)
    line = _policies_applied(rows)
    assert "ordering: warn on 1 log(s), summary: drop on 1 log(s)" in line


def test_no_hint_when_no_analysis_warned():
    rows = [r for r in _rows() if r["analysis"] == "summary"]
    line = _policies_applied(rows)
    assert line == "outlier policy applied: summary: drop on 2 log(s)"
