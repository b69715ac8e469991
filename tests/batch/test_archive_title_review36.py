"""Mutation round 36 (review36): the archive plot's title counts the logs drawn.

The plant ``len(drawn) < total`` -> ``<=`` (every title "N of M logs") escaped stop 60's
tests, which never read the title. Reference: the rows given (how many are dated, by
Python's ``datetime.fromisoformat``), and the title matplotlib holds at ``savefig``.
"""

from __future__ import annotations

from matplotlib.figure import Figure

from modalinfo.batch.report import plot_archive


def _row(path: str, date, rms: float) -> dict:
    return {"path": path, "analysis": "summary", "status": "ok", "date": date,
            "rms_total": rms, "units": "rad", "n_modes": 10}


def _titles(monkeypatch, rows, tmp_path) -> list[str]:
    seen = []
    original = Figure.savefig

    def kept(self, *args, **kwargs):
        seen.append(self._suptitle.get_text() if self._suptitle is not None else "")
        return original(self, *args, **kwargs)

    monkeypatch.setattr(Figure, "savefig", kept)
    plot_archive(rows, tmp_path)
    return seen


def test_all_logs_drawn_say_the_archive(monkeypatch, tmp_path):
    rows = [_row("a.npz", "2026-11-01T20:00:00", 1.0), _row("b.npz", "2026-11-02", 2.0)]
    assert "archive of 2 logs against date" in _titles(monkeypatch, rows, tmp_path)


def test_some_logs_undrawn_are_counted(monkeypatch, tmp_path):
    rows = [_row("a.npz", "2026-11-01T20:00:00", 1.0), _row("b.npz", "2026-11-02", 2.0),
            _row("c.npz", 61345.5, 3.0)]
    assert "2 of 3 logs of the archive against date" in _titles(monkeypatch, rows, tmp_path)
