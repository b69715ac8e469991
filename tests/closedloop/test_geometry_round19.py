"""Guide-star field geometry at its edges (adversarial round 19 PART a, issue 27).

Reference: the meta-pupil law ``D + 2 h sec(z) tan(fov / 2)`` evaluated here by hand.
A WFS conjugated at 1000 km with a 10" field senses a 49 m meta-pupil on a 0.7 m
telescope: its build grows as (49 / 0.7)**2 ~ 4,900 times a ground WFS's, against 19
field directions, so the refusal must name its altitude, not its field sampling.
"""

from __future__ import annotations

import dataclasses as dc
import math

from closedloop import presets
from closedloop.config import SimulationConfig, wfs_meta_pupil
from closedloop.resources import estimate

ARCSEC = math.pi / 180 / 3600


def _at(config, altitude):
    changed = dc.replace(config, dms=(dc.replace(config.dms[0], altitude=altitude),),
                         wfss=(dc.replace(config.wfss[0], altitude=altitude),))
    return SimulationConfig(**{f.name: getattr(changed, f.name) for f in dc.fields(changed)})


def test_meta_pupil_follows_the_law_at_1000_km():
    cfg = _at(presets.get("kaos"), 1e6)
    want = 0.7 + 2 * 1e6 * math.tan(5 * ARCSEC)
    assert math.isclose(wfs_meta_pupil(cfg, 0), want, rel_tol=1e-12)


def test_wfs_build_of_a_high_conjugate_names_its_altitude():
    est = estimate(_at(presets.get("kaos"), 1e6), 0.01)
    assert est.drivers["wfs_build"].startswith("wfss[0].altitude")


def test_wfs_build_on_the_ground_still_names_the_field_sampling():
    est = estimate(presets.get("kaos"), 0.01)
    assert est.drivers["wfs_build"].startswith("wfss[0].field_samples")
