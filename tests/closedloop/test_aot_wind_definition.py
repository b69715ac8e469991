"""The AOT wind-direction definition our export converts to is the one aotpy ships.

Reference: the AOT standard as its reference implementation ``aotpy`` states it
(``aotpy/core/atmosphere.py``, ``AtmosphericParameters.layers_wind_direction``): "Wind
direction of each l turbulence layer, for each time instant, with 0° being North,
increasing eastward" (deg). The standard does not say "to" or "from"; aotpy's ESO
translators write ESO's ambient ``TEL AMBI WINDDIR`` (a meteorological, from-direction
azimuth, N = 0, E = 90) into that field unchanged, while they convert ESO's telescope
azimuth (S = 0, W = 90) with ``_azimuth_conversion``: the evidence for our "from"
reading (``closedloop.aot.aot_wind_direction``; the conversion itself is tested in
``test_aot_wind.py``). If a new aotpy changes either text, these tests fail and the
conversion must be reviewed against the new definition.
"""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import pytest

from closedloop.aot import WIND_CONVENTION, aot_wind_direction

aotpy = pytest.importorskip("aotpy")


def _source(module: str) -> str:
    """Text of an aotpy module, whitespace collapsed (read, not imported)."""
    spec = importlib.util.find_spec(module)
    if spec is None or spec.origin is None:
        pytest.skip(f"{module} not installed")
    return re.sub(r"\s+", " ", Path(spec.origin).read_text(encoding="utf-8"))


def test_aotpy_defines_the_azimuth_we_convert_to():
    text = _source("aotpy.core.atmosphere")
    assert re.search(r"layers_wind_direction: Image = None \"\"\"Wind direction of each "
                     r".*?with 0° being North, increasing eastward\. .*?in deg units", text)
    # our card states the same azimuth
    assert "0 = North, increasing eastward" in WIND_CONVENTION


@pytest.mark.parametrize("module", ["aotpy.translators.naomi", "aotpy.translators.ciao"])
def test_aotpy_fills_the_field_with_esos_from_direction_unchanged(module):
    text = _source(module)
    assert ("layers_wind_direction=aotpy.Image('ESO TEL AMBI WINDDIR', "
            "np.array([[main_hdr['ESO TEL AMBI WINDDIR']]]))") in text
    # while the telescope azimuth, in ESO's other frame, is converted
    assert "azimuth=self._azimuth_conversion(main_hdr['ESO TEL AZ'])" in text


def test_a_wind_from_the_north_blowing_south():
    # hand case in the definition's own words: a layer moving towards -y (South on our
    # map, +x = East, +y = North) comes from the North, azimuth 0; from the East, 90
    assert float(aot_wind_direction(270.0)) == pytest.approx(0.0, abs=1e-12)
    assert float(aot_wind_direction(180.0)) == pytest.approx(90.0, abs=1e-12)
