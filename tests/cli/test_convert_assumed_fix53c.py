"""Stop 59's small items (fix53-c, issue 27): ``convert`` keeps "assumed" units assumed.

docs/MUTATION.md, review35 "Noticed": does ``convert`` of a foreign file without units
write the rad it assumed as if the file had stated it? Reference: a round trip (the file
is written by h5py, with and without a ``units`` attribute; the copy is read back by
``load`` / ``info``): a source without units gives a copy whose units read "assumed" in
every format convert writes, and a source stating nm gives a copy stating nm.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import load


def _source(tmp_path, units=None):
    path = tmp_path / ("stated.h5" if units else "bare.h5")
    with h5py.File(path, "w") as f:
        d = f.create_dataset("coeffs", data=np.random.default_rng(53).normal(size=(200, 4)))
        if units:
            d.attrs["units"] = units
    return path


@pytest.mark.parametrize("out", ["o.npz", "o.h5", "o.fits", "o.csv"])
def test_assumed_units_stay_assumed_through_convert(tmp_path, capsys, out):
    src = _source(tmp_path)
    assert main(["convert", str(src), str(tmp_path / out), "--rate", "1000", "--quiet"]) == 0
    copy = load(tmp_path / out)
    assert copy.units == "rad"
    assert "units" in copy.metadata.get("assumed", {})
    capsys.readouterr()
    assert main(["info", str(tmp_path / out)]) == 0
    units_line = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("units")]
    assert units_line and "(assumed)" in units_line[0]


@pytest.mark.parametrize("out", ["o.npz", "o.h5", "o.fits", "o.csv"])
def test_stated_units_stay_stated_through_convert(tmp_path, out):
    src = _source(tmp_path, units="nm")
    assert main(["convert", str(src), str(tmp_path / out), "--rate", "1000", "--quiet"]) == 0
    copy = load(tmp_path / out)
    assert copy.units == "nm"
    assert "units" not in copy.metadata.get("assumed", {})
