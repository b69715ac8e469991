"""The meta-pupil refusal's advice on an unobscured pupil (review23, issue 27).

docs/MUTATION.md, "Planted bugs, round 23", R23-M2: round 31's refusal of a field too
wide for its sensor's altitude advises "a smaller obscuration" only where there is one;
no test read the advice on an unobscured pupil, so advising it there escaped.

Reference (outside the code): the meta-pupil law ``D + 2 h tan(theta / 2)`` (Ragazzoni,
Farinato & Marchetti 2000, computed with ``math``): the advice followed (a field of 60"
at 20 km: a 9.8-m meta-pupil, 8 subapertures of 1.2 m, the central ones lit by the 4-m
pupil) gives a sensor; an obscuration of 0 cannot be made smaller.
"""

import math

import pytest

from closedloop.simulation import LoopModel

from .test_metapupil_refusal_round31 import _config

ARCSEC = math.pi / 180.0 / 3600.0


def test_an_unobscured_pupil_is_not_told_to_shrink_its_obscuration():
    cfg = _config(20e3, 600.0)
    assert cfg.telescope.obscuration == 0.0
    with pytest.raises(ValueError) as err:
        LoopModel(cfg)
    text = str(err.value)
    assert text.endswith("use more subapertures, a smaller field or a lower altitude")
    assert "smaller obscuration" not in text
    # the advice followed: a field whose meta-pupil the pupil lights
    d_wfs = 4.0 + 2.0 * 20e3 * math.tan(30.0 * ARCSEC)
    assert d_wfs / 8 < 4.0 / 2  # a subaperture well inside the pupil's footprint
    model = LoopModel(_config(20e3, 60.0))
    assert model.wfss[0].valid_subapertures.size > 0
