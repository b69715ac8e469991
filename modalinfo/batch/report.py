"""Summary plots across an archive of logs.

Forecast gain, MI-order stability and RMS against date, seeing or loop rate
(whichever the logs' metadata provide).

One figure per x quantity present in the rows (``date``, ``r0_m`` / ``seeing_arcsec``,
``rate``; a date is an ISO 8601 text, placed in UTC, one without an offset taken as UTC),
with one panel per y quantity present (forecast gain at h = 1 per
predictor, consecutive-window Spearman correlation of the MI ordering, total RMS).
"""

from __future__ import annotations

import itertools
import math
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

__all__ = ["plot_archive", "remove_stale_plots"]

_X = (("date", "date"), ("r0_m", "r0 [m]"), ("seeing_arcsec", "seeing [arcsec]"),
      ("rate", "loop rate [Hz]"))


def _number(value: Any) -> float | None:
    if isinstance(value, bool) or value is None:
        return None
    if isinstance(value, int | float):
        return float(value) if math.isfinite(value) else None
    return None


def _x_value(row: dict, name: str) -> Any:
    """Return a row's x quantity ``name``, or None where it cannot be placed.

    A date is an ISO 8601 text only, placed as UTC: one with an offset (``+02:00``,
    ``Z``, a Unix ``start_time``'s ``+00:00``) is converted to UTC, one without is taken
    as UTC already. Naive and aware dates together raised "can't compare offset-naive
    and offset-aware datetimes" after every task had run, exit 2 and no summary, and a
    number (an MJD, ``20261101``) was drawn as the date itself, 20 million "days" from
    its neighbour, or raised against a date (adversarial round 53 PART b, O01-O23): a
    number is no date here and is not placed.
    """
    value = row.get(name)
    if name == "date":
        if not isinstance(value, str):
            return None
        try:
            when = datetime.fromisoformat(value.strip())
        except ValueError:
            return None
        if when.tzinfo is not None:
            when = when.astimezone(UTC).replace(tzinfo=None)
        return when
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
        out.append(("summary", "rms_total", "total RMS"))
    return out


def _rms_group(row: dict) -> str:
    """Legend of a summary row's total RMS: its units and mode count (``"nm, 20 modes"``)."""
    units = row.get("units") if isinstance(row.get("units"), str) else "units unknown"
    n_modes = _number(row.get("n_modes"))
    return units if n_modes is None else f"{units}, {int(n_modes)} modes"


def _panels(rows: list[dict], x_name: str) -> list[tuple[str, dict[str, list]]]:
    """Return the panels of one figure: (y label, {series legend: sorted (x, y) points}).

    The total RMS of logs in other units (nm, rad, waves) or over other modes is not
    one quantity: one series per (units, mode count), the label saying they are not
    comparable; one series alone is labelled with its units. Before, one series of
    "total RMS [log units]" put the same log in nm, rad and waves at three heights
    (adversarial round 27 PART b, N08).
    """
    panels = []
    for analysis, column, label in _series(rows):
        series: dict[str, list] = {}
        for r in rows:
            if r.get("analysis") != analysis or r.get("status") != "ok":
                continue
            x, y = _x_value(r, x_name), _number(r.get(column))
            if x is None or y is None:
                continue
            series.setdefault(_rms_group(r) if column == "rms_total" else "", []).append((x, y))
        if sum(len(v) for v in series.values()) < 2:
            continue
        if column == "rms_total":
            if len(series) == 1:
                label = f"total RMS [{next(iter(series))}]"
            else:
                label = "total RMS [each log's units]: series not comparable"
        panels.append((label, {k: sorted(v) for k, v in series.items()}))
    return panels


def remove_stale_plots(out_dir: str | Path, table_sha256: str) -> list[Path]:
    """Remove the summary plots in ``out_dir`` that were not drawn from this table.

    A run with ``plots=False`` (``--no-plots``) into the folder of an earlier run left
    that run's ``archive_vs_<x>.png`` beside the new table, which they do not show
    (a forecast horizon changed: the gains drawn were the old horizon's; adversarial
    round 54 PART b, P88). A plot whose PNG record names this table's SHA-256 is kept
    (the same rows, re-tabled); one of another table, or without a readable record, is
    derived from rows no longer tabled and is removed.

    Parameters
    ----------
    out_dir : path
        The ``plots`` folder of a batch output (need not exist).
    table_sha256 : str
        SHA-256 of the table just written (``batch.csv``).

    Returns
    -------
    list of pathlib.Path
        The files removed.
    """
    import json

    from PIL import Image

    removed = []
    for x_name, _ in _X:
        path = Path(out_dir) / f"archive_vs_{x_name}.png"
        if not path.is_file():
            continue
        try:
            with Image.open(path) as image:
                record = json.loads(image.info.get("Description") or "{}")
        except (OSError, ValueError):
            record = {}
        if not isinstance(record, dict) or record.get("table_sha256") != table_sha256:
            path.unlink(missing_ok=True)
            removed.append(path)
    return removed


def plot_archive(rows: list[dict], out_dir: str | Path, *,
                 provenance: dict | None = None) -> list[Path]:
    """Draw the summary plots of a batch table into ``out_dir`` (created if missing).

    Parameters
    ----------
    rows : list of dict
        Rows of :func:`~modalinfo.batch.analyse_archive`.
    out_dir : path
        Directory of the PNG files (replaced on each run: they are derived from the
        rows; an ``archive_vs_<x>.png`` this run does not draw is removed).
    provenance : dict, optional
        What made the plots (``analyse_archive`` passes the batch's record: version,
        command, the table's SHA-256), written as JSON in each PNG's ``Description``
        text chunk (``modalinfo.common.provenance.png_metadata``).

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
    from modalinfo.common.provenance import png_metadata

    meta = png_metadata(provenance)
    with drawable_rc():  # the user's matplotlibrc, less what cannot draw here
        written = []
        for x_name, x_label in _X:
            panels = _panels(rows, x_name)
            if not panels:
                # a plot an earlier run drew against this quantity is of other rows: it
                # was left beside the new table, which it did not draw (adversarial
                # round 53 PART b, O06 / O08)
                (Path(out_dir) / f"archive_vs_{x_name}.png").unlink(missing_ok=True)
                continue
            out = Path(out_dir)
            out.mkdir(parents=True, exist_ok=True)
            fig = Figure(figsize=(7, 2.4 * len(panels) + 0.6))
            axes = fig.subplots(len(panels), 1, sharex=True, squeeze=False)
            for ax, (label, series) in zip(axes[:, 0], panels, strict=True):
                for (legend, pts), marker in zip(series.items(), itertools.cycle("osD^v<>px*")):
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker, ms=4,
                            label=legend or None)
                if len(series) > 1:
                    ax.legend(fontsize=7)
                ax.set_ylabel(label, fontsize=8)
                ax.grid(alpha=0.3)
            axes[-1, 0].set_xlabel(x_label)
            if x_name == "date":
                fig.autofmt_xdate()
            # the logs drawn, not the table's: a log without a placeable x was counted
            # in "archive of 3 logs against date" over 2 points (round 53 PART b, O19)
            drawn = {r.get("path") for r in rows if r.get("status") == "ok"
                     and _x_value(r, x_name) is not None}
            total = len({r.get("path") for r in rows})
            fig.suptitle(f"{len(drawn)} of {total} logs of the archive against {x_label}"
                         if len(drawn) < total else
                         f"archive of {total} logs against {x_label}")
            fig.tight_layout()
            path = out / f"archive_vs_{x_name}.png"
            atomic_write(path, lambda fh, f=fig: f.savefig(fh, format="png", dpi=120,
                                                          metadata=meta),
                         overwrite=True)
            written.append(path)
    return written
