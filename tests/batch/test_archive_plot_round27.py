"""Round 27 PART b of issue 27: the archive plot does not put logs in other units on one axis.

docs/ADVERSARIAL.md, "Round 27 PART b, issue 27", row N08.

Reference: the same AR(1) series written three times, in rad, nm and waves at 500 nm
(nm = rad x 500 / (2 pi), waves = rad / (2 pi), the definitions of the units), whose
total RMS therefore differs by those exact factors: one axis of "total RMS" over the
three compares numbers of different units. The test builds the rows by hand from
those factors (``numpy``), so no batch analysis is run.
"""

from __future__ import annotations

import math

from modalinfo.batch.report import _panels, plot_archive


def _row(path, units, rms, n_modes=20, rate=2000.0):
    return {"path": path, "analysis": "summary", "status": "ok", "units": units,
            "rms_total": rms, "n_modes": n_modes, "rate": rate}


RAD = 0.4507
ROWS = [_row("a_rad.npz", "rad", RAD), _row("a_nm.npz", "nm", RAD * 500 / (2 * math.pi)),
        _row("a_waves.npz", "waves", RAD / (2 * math.pi)),
        _row("b_nm.h5", "nm", 64.1, n_modes=65, rate=500.0)]


def test_mixed_units_are_separate_series_said_not_comparable():
    # Before: one series "total RMS [log units]" of 0.45, 35.9 and 0.072 for one log.
    [(label, series)] = _panels(ROWS, "rate")
    assert "not comparable" in label
    assert set(series) == {"rad, 20 modes", "nm, 20 modes", "waves, 20 modes",
                           "nm, 65 modes"}
    for legend, pts in series.items():  # each series holds only rows of its own units
        units = legend.split(",")[0]
        assert all(any(r["units"] == units and r["rms_total"] == y for r in ROWS)
                   for _, y in pts)


def test_one_unit_labels_the_axis_with_it(tmp_path):
    rows = [_row("x.npz", "nm", 30.0), _row("y.npz", "nm", 40.0, rate=500.0)]
    [(label, series)] = _panels(rows, "rate")
    assert label == "total RMS [nm, 20 modes]" and list(series) == ["nm, 20 modes"]
    assert [p.name for p in plot_archive(ROWS, tmp_path)] == ["archive_vs_rate.png"]
