"""The archive plots against date with the date forms archives hold (round 53 PART b, O01-O23).

Reference: Python's ``datetime`` (an ISO 8601 date with an offset is the UTC instant
``datetime.fromisoformat(text).astimezone(UTC)``; 2026-11-02T20:00:00+02:00 is
2026-11-02T18:00:00 UTC), and the files ``plot_archive`` leaves in its folder (a plot not
drawn from these rows must not be there).
"""

from __future__ import annotations

from datetime import datetime

from modalinfo.batch.report import _panels, plot_archive


def _row(path: str, date, rms: float) -> dict:
    return {"path": path, "analysis": "summary", "status": "ok", "date": date,
            "rms_total": rms, "units": "rad", "n_modes": 10}


def test_naive_and_aware_dates_drawn_in_utc(tmp_path):
    rows = [_row("a.npz", "2026-11-01T20:00:00", 1.0),
            _row("b.npz", "2026-11-02T20:00:00+02:00", 2.0),
            _row("c.npz", "2026-11-03T10:00:00+00:00", 3.0),
            _row("d.npz", "2026-11-04T01:00:00Z", 4.0)]
    written = plot_archive(rows, tmp_path)  # raised "can't compare offset-naive and ..."
    assert tmp_path / "archive_vs_date.png" in written
    (label, series), = _panels(rows, "date")
    assert [p[0] for p in series["rad, 10 modes"]] == [
        datetime(2026, 11, 1, 20), datetime(2026, 11, 2, 18), datetime(2026, 11, 3, 10),
        datetime(2026, 11, 4, 1)]


def test_numbers_are_not_placed_as_dates(tmp_path):
    rows = [_row("mjd.npz", 61345.5, 1.0), _row("int.npz", 20261101, 2.0),
            _row("a.npz", "2026-11-01T20:00:00", 3.0)]
    # the two numbers were drawn as x = 61345.5 and 20261101 on the date axis, or raised
    # "'<' not supported between instances of 'datetime.datetime' and 'float'"
    assert plot_archive(rows, tmp_path) == []
    assert _panels(rows, "date") == []


def test_plot_not_drawn_this_run_is_removed(tmp_path):
    dated = [_row("a.npz", "2026-11-01T20:00:00", 1.0), _row("b.npz", "2026-11-04", 2.0)]
    assert tmp_path / "archive_vs_date.png" in plot_archive(dated, tmp_path)
    undated = [_row("a.npz", "2026-11-01T20:00:00", 1.0), _row("e.npz", "04/11/2026", 2.0)]
    assert plot_archive(undated, tmp_path) == []
    # the first run's date plot, of other rows, stayed beside the new table
    assert not (tmp_path / "archive_vs_date.png").exists()


def test_title_counts_the_logs_drawn(tmp_path, monkeypatch):
    from matplotlib.figure import Figure

    titles = []
    original = Figure.suptitle
    monkeypatch.setattr(Figure, "suptitle",
                        lambda self, text, **kw: titles.append(text) or original(self, text, **kw))
    rows = [_row("a.npz", "2026-11-01T20:00:00", 1.0), _row("b.npz", "2026-11-07T20:00:00", 2.0),
            _row("w.npz", "last night", 3.0)]
    plot_archive(rows, tmp_path)
    # "archive of 3 logs against date" over the 2 points drawn (O19)
    assert "2 of 3 logs of the archive against date" in titles
