"""Planted-bug review 18 (issue 27): which factor the WFS build's driver names.

Round 19 PART a (g17) made ``closedloop.resources.estimate`` name a high-conjugate
WFS's altitude when its build grows more by the widened meta-pupil than by its field
directions: the build scales as ``samples x (meta-pupil / D)**2``. The round's tests
took 1000 km (a widening of ~4,900 against 19 directions) and the ground (1), where any
power of the ratio decides alike. Here the ratio itself is below the 19 directions and
its square above (or below) them.

Reference: the meta-pupil law ``D + 2 h tan(fov / 2)`` (zenith 0) evaluated by hand for
the KAOS preset (D = 0.7 m, a 10 arcsec field, 3 rings of ``1 + 3 r (r - 1)`` = 19
directions), and the area (square) scaling stated.
"""

from __future__ import annotations

import dataclasses as dc
import math

import pytest

from closedloop import presets
from closedloop.config import SimulationConfig
from closedloop.resources import estimate

ARCSEC = math.pi / 180 / 3600


def _at(config, altitude):
    changed = dc.replace(config, dms=(dc.replace(config.dms[0], altitude=altitude),),
                         wfss=(dc.replace(config.wfss[0], altitude=altitude),))
    return SimulationConfig(**{f.name: getattr(changed, f.name) for f in dc.fields(changed)})


@pytest.mark.parametrize("altitude", [30e3, 80e3])
def test_driver_named_by_the_area_widening_against_the_directions(altitude):
    base = presets.get("kaos")
    rings = base.wfss[0].field_samples
    samples = 1 + 3 * rings * (rings - 1)  # hexagonal grid (WFSConfig docs): 19 at 3 rings
    assert samples == 19
    ratio = (0.7 + 2 * altitude * math.tan(5 * ARCSEC)) / 0.7  # 3.1 and 6.5
    assert ratio < samples
    est = estimate(_at(base, altitude), 0.01)
    want = "altitude" if ratio ** 2 > samples else "field_samples"
    assert est.drivers["wfs_build"].startswith(f"wfss[0].{want}")
