"""A batch row says what its log's reader assumed, as every command's note does.

Adversarial round 41 PART b, issue 27 (row B02): ``modalinfo batch`` over a night's
folder holding a raw ``.npy`` array (no units, no modes recorded) wrote a summary row
with ``units`` "rad" and ``largest_mode`` "Z2" and no word that both were assumed, where
``info`` / ``reorder`` / ``fitting-error`` say "does not record its units, modes:
assumed units rad, modes Z2..Z5 (noll)". Reference, outside the code: the file itself,
written by ``numpy.save``, which stores an array and nothing else; and a file that does
record its units and modes (``modalinfo.io.save`` of a ModalLog) gets no such column.
"""

from __future__ import annotations

import numpy as np

import modalinfo.io as mio
from modalinfo.batch.analyses import log_columns
from modalinfo.telemetry import ModalLog


def test_a_raw_npy_row_names_the_assumed_units_and_modes(tmp_path):
    path = tmp_path / "raw.npy"
    np.save(path, np.random.default_rng(41).standard_normal((300, 4)))
    row = log_columns(mio.load(path))
    assert row["units"] == "rad"
    assert row["assumed"] == "units rad, modes Z2..Z5 (noll)"


def test_a_row_of_a_log_that_records_them_has_no_assumed_column(tmp_path):
    log = ModalLog(np.random.default_rng(41).standard_normal((300, 4)), rate=1000.0,
                   modes=[2, 3, 4, 5], units="nm", wavelength=1e-6)
    path = mio.save(log, tmp_path / "native.npz")
    assert "assumed" not in log_columns(mio.load(path))
