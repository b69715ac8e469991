"""Summary plots across an archive of logs.

Forecast gain, MI-order stability and RMS against date, seeing or loop rate
(whichever the logs' metadata provide).

One figure per x quantity present in the rows (``date``, ``r0_m`` / ``seeing_arcsec``,
``rate``), with one panel per y quantity present (forecast gain at h = 1 per
predictor, consecutive-window Spearman correlation of the MI ordering, total RMS).
"""

from __future__ import annotations

import math
from datetime import datetime
from pathlib import Path
from typing import Any

__all__ = ["plot_archive"]

_X = (("date", "date"), ("r0_m", "r0 [m]"), ("seeing_arcsec", "seeing [arcsec]"),
      ("rate", "loop rate [Hz]"))


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, int | float):
        return float(value) if math.isfinite(value) else None
    return None


def _x_value(row: dict, name: str) -> Any:
    value = row.get(name)
    if name == "date" and isinstance(value, str):
        try:
            return datetime.fromisoformat(value)
        except ValueError:
            return None
    return _number(value)


def _series(rows: list[dict]) -> list[tuple[str, str, str]]:
    """(analysis, column, axis label) of the y quantities present."""
    out = []
    gains = sorted({k for r in rows if r.get("analysis") == "forecast" and r.get("status") == "ok"
                    for k in r if k.startswith("gain_h1.")})
    for column in gains:
        out.append(("forecast", column, f"gain over persistence, h=1: {column[8:]}"))
    if any(r.get("analysis") == "ordering" and "window_spearman" in r for r in rows):
        out.append(("ordering", "window_spearman", "MI order stability (Spearman)"))
    if any(r.get("analysis") == "summary" and r.get("status") == "ok" for r in rows):
        out.append(("summary", "rms_total", "total RMS [log units]"))
    return out


def plot_archive(rows: list[dict], out_dir: str | Path) -> list[Path]:
    """Draw the summary plots of a batch table into ``out_dir`` (created if missing).

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`~modalinfo.batch.analyse_archive`.
    out_dir : path
        Directory of the PNG files (replaced on each run: they are derived from the
        rows).

    Returns
    -------
    list of pathlib.Path
        Files written (none when no x or y quantity is present in two rows or more).
    """
    # a Figure of its own (no pyplot): matplotlib.use("Agg") switched the caller's backend,
    # e.g. a notebook's, for good at every analyse_archive (audit 10-state, row
    # glob-plot_archive); Figure.savefig draws with the Agg canvas all the same
    from matplotlib.figure import Figure

    from modalinfo.common.files import atomic_write
    from modalinfo.common.plotting import drawable_rc

    with drawable_rc():  # the user's matplotlibrc, less what cannot draw here
        ys = _series(rows)
        written = []
        for x_name, x_label in _X:
            panels = []
            for analysis, column, label in ys:
                pts = [(_x_value(r, x_name), _number(r.get(column))) for r in rows
                       if r.get("analysis") == analysis and r.get("status") == "ok"]
                pts = [(x, y) for x, y in pts if x is not None and y is not None]
                if len(pts) >= 2:
                    panels.append((label, sorted(pts)))
            if not panels:
                continue
            out = Path(out_dir)
            out.mkdir(parents=True, exist_ok=True)
            fig = Figure(figsize=(7, 2.4 * len(panels) + 0.6))
            axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)
            for ax, (label, pts) in zip(axes[:, 0], panels, strict=True):
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "o", ms=4)
                ax.set_ylabel(label, fontsize=8)
                ax.grid(alpha=0.3)
            axes[-1, 0].set_xlabel(x_label)
            if x_name == "date":
                fig.autofmt_xdate()
            fig.suptitle(f"archive of {len({r.get('path') for r in rows})} logs against {x_label}")
            fig.tight_layout()
            path = out / f"archive_vs_{x_name}.png"
            atomic_write(path, lambda fh, f=fig: f.savefig(fh, format="png", dpi=120),
                         overwrite=True)
            written.append(path)
    return written
