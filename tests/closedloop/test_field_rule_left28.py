"""A layer-oriented Shack-Hartmann at altitude: its valid set, its weights, its pupil edge.

Issue 27 (docs/CLOSEDLOOP.md, "A DM conjugated to a high layer"; docs/ADVERSARIAL.md,
"Leftovers 28-field"). References (outside the code under test):

- the valid-subaperture rule of layer-oriented sensing written out on a toy table of lit
  weights: a subaperture is used when some direction lights half of it (the whole
  meta-pupil of Ragazzoni, Farinato & Marchetti 2000), its light share the light it
  collects over ``n`` directions relative to ``n`` times a fully lit one's (left31-edge;
  relative to its best direction's before);
- the inverse-variance law (Gauss-Markov; Wallner 1983, Ellerbroek 2002 for AO): two
  measurements ``m_i`` of one quantity with variances ``sigma^2 / s_i`` are best combined
  as ``sum s_i m_i / sum s_i``, with variance ``sigma^2 / sum s_i``, computed here by hand;
- the pupil's geometry, computed here from the plane's pixel grid: a sensor conjugated to
  altitude must read only ground-plane pixels whose centres lie inside the telescope
  pupil (a bilinear sample within a pixel of the edge reads the zeros beyond the ground
  DM's disc, a step the turbulence does not have);
- the noise law of a co-added measurement: photon noise variance ``sigma^2 / share``, with
  ``sigma`` from the config (``2 pi alpha / lambda``), computed here.
"""

import dataclasses as dc
import functools
import math

import numpy as np
import pytest

from closedloop import presets
from closedloop.optics.dm import ZernikeMirror
from closedloop.optics.geometry import Geometry
from closedloop.optics.wfs import ShackHartmann, field_rule

ARCSEC = math.pi / 648000.0


def test_field_rule_keeps_what_some_direction_half_lights():
    full = 4.0
    # two directions x five subapertures: lit weight of each seen from each direction
    lit = np.array([[4.0, 4.0, 1.6, 1.2, 2.4],
                    [4.0, 0.0, 0.0, 1.2, 0.8]])
    valid, share = field_rule(lit.sum(axis=0), lit.max(axis=0), 2, full)
    # 0: both full; 1: one full (half the field's light); 2: 40 % from one only;
    # 3: 30 % from both (the old field-averaged rule also dropped it); 4: 60 % and 20 %,
    # the light of 0.4 of a fully lit one (left31-edge; over its best direction's, 2/3,
    # before)
    assert valid.tolist() == [0, 1, 4]
    np.testing.assert_allclose(share, [1.0, 0.5, (2.4 + 0.8) / (2 * 4.0)], rtol=1e-15)


def test_a_ground_sensor_has_share_exactly_one_where_fully_lit():
    one = np.array([3.0, 0.1 + 0.2, 2.0])      # 0.1 + 0.2: a sum that is not exact
    valid, share = field_rule(sum([one] * 7), one, 7, 3.0)
    # the fully lit one exactly 1; the 2/3-lit one its lit area (left31-edge; 1 before)
    assert valid.tolist() == [0, 2] and share[0] == 1.0
    assert share[1] == pytest.approx(2.0 / 3.0, rel=1e-15)


class _Mirror:
    large_products = False


def _toy_sensor(interaction: np.ndarray, share: np.ndarray) -> ShackHartmann:
    """A Shack-Hartmann shell holding only what its least-squares reconstructor reads."""
    wfs = object.__new__(ShackHartmann)
    wfs.__dict__["interaction"] = interaction     # the cached property, set
    wfs.field_share = share
    wfs.dm = _Mirror()
    return wfs


def test_weighting_is_the_inverse_variance_law_on_two_measurements():
    share = np.array([1.0, 0.25])                 # variance sigma^2 and 4 sigma^2
    wfs = _toy_sensor(np.array([[1.0], [1.0]]), share)
    r = wfs._least_squares(1e-3)
    m = np.array([0.3, -1.1])
    expected = (share * m).sum() / share.sum()    # Gauss-Markov, by hand
    np.testing.assert_allclose(r @ m, [expected], rtol=1e-12)
    sigma2 = 0.7
    var = r @ np.diag(sigma2 / share) @ r.T
    np.testing.assert_allclose(var, [[sigma2 / share.sum()]], rtol=1e-12)


def test_equal_shares_leave_the_plain_pseudo_inverse():
    g = np.array([[1.0, 0.2], [0.3, 1.0], [0.5, -0.4]])
    r = _toy_sensor(g, np.ones(3))._least_squares(1e-3)
    np.testing.assert_array_equal(r, np.linalg.pinv(g, rcond=1e-3))


@functools.lru_cache(maxsize=1)
def _table1_upper_wfs():
    cfg = presets.get("table1")
    cfg = dc.replace(cfg, dms=(cfg.dms[1],), wfss=(dc.replace(cfg.wfss[1], dm=0),))
    g = Geometry(cfg)
    return cfg, g, ShackHartmann(g, 0, ZernikeMirror(g, 0))


def test_sensor_at_altitude_reads_no_ground_pixel_outside_the_pupil():
    cfg, g, wfs = _table1_upper_wfs()
    ground = int(np.argmin([p.altitude for p in g.planes]))
    assert g.planes[ground].altitude == 0.0
    n = g.planes[ground].n
    coords = g.plane_coords(ground)
    read = np.unique(wfs.operators[ground].indices)
    r = np.hypot(coords[read % n], coords[read // n])
    outside = int((r > cfg.telescope.diameter / 2.0 + 1e-9).sum())
    assert outside == 0, f"{outside} ground pixels beyond the pupil are read"


def test_noise_grows_as_the_inverse_share_of_the_field():
    cfg, g, wfs = _table1_upper_wfs()
    sigma = 2.0 * math.pi * cfg.wfss[0].noise * ARCSEC / cfg.r0_wavelength
    share = wfs.field_share
    assert share.min() < 0.2 and share.max() == 1.0   # the meta-pupil's ring is used
    np.testing.assert_allclose(np.asarray(wfs.noise_rms) ** 2, sigma ** 2 / share,
                               rtol=1e-12)
    r0s = [g.layer_r0(i) for i in range(len(cfg.layers))]
    me = np.asarray(wfs.model_error_variance(r0s, 0.3))
    np.testing.assert_allclose(me * share, me[share == 1.0][0], rtol=1e-12)


def test_a_ground_sensor_keeps_the_configured_noise_where_fully_lit():
    # its pupil-edge subapertures collect less light (test_lit_share_left31); the others
    # keep the configured noise to the bit
    cfg = presets.get("table1")
    g = Geometry(cfg)
    wfs = ShackHartmann(g, 0, ZernikeMirror(g, 0))
    assert cfg.wfss[0].altitude == 0.0
    sigma = 2.0 * math.pi * cfg.wfss[0].noise * ARCSEC / cfg.r0_wavelength
    full = wfs.field_share == 1.0
    assert 0 < (~full).sum() < full.sum()
    assert np.all(np.asarray(wfs.noise_rms)[full] == sigma)
