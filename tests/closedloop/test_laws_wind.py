"""Wind inside the loop: a layer's phase moves by (v cos a, v sin a) T per frame.

Reference: frozen flow and the axis conventions of DESIGN.md (x along columns, y along
rows, wind direction measured from +x towards +y, the pattern moving *with* the wind).
The displacement between two residual snapshots one frame apart is measured in the test
by cross-correlating their x-gradients (nearly white for Kolmogorov phase, so the peak is
sharp) over the pupil, with a parabolic sub-pixel fit of the peak; the loop runs at a
negligible gain, so the residual is the turbulence. Ground and high layers, several
directions including oblique ones and every quadrant.
"""

import math

import numpy as np
import pytest

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.simulation import simulate

N_PIXELS = 48
DX = 4.0 / N_PIXELS
T = 5e-3  # 200 Hz: 3 pixels a frame at 50 m/s (left26-twins: winds <= 100 m/s)


def _config(speed, direction, altitude, field=None):
    return SimulationConfig(
        name="wind",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=N_PIXELS),
        layers=(LayerConfig(altitude=altitude, d_over_r0=15.0, wind_speed=speed,
                            wind_direction=direction),),
        dms=(DMConfig(altitude=0.0, n_modes=5),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", field_samples=1),),
        # a negligible gain: the residual is the turbulence (to 1e-9 of it)
        loop=LoopConfig(time_step=T, integration_time=T, delay=0.0, gain=1e-9),
        field=field or FieldConfig(size=0.0, n_points=1), wavelength=500e-9,
        r0_wavelength=500e-9)


def _displacement(a, b, max_shift=7):
    """(dx, dy) [pixels] with b(x, y) ~ a(x - dx, y - dy), from gradient cross-correlation."""
    ga = np.diff(a, axis=1)
    gb = np.diff(b, axis=1)
    n = ga.shape[0]
    corr = np.full((2 * max_shift + 1, 2 * max_shift + 1), -np.inf)
    for i, dy in enumerate(range(-max_shift, max_shift + 1)):
        for j, dx in enumerate(range(-max_shift, max_shift + 1)):
            # b[r, c] against a[r - dy, c - dx] over the overlap
            sb = gb[max(dy, 0):n + min(dy, 0), max(dx, 0):ga.shape[1] + min(dx, 0)]
            sa = ga[max(-dy, 0):n + min(-dy, 0), max(-dx, 0):ga.shape[1] + min(-dx, 0)]
            ok = np.isfinite(sa) & np.isfinite(sb)
            if ok.sum() > 200:
                x, y = sa[ok] - sa[ok].mean(), sb[ok] - sb[ok].mean()
                corr[i, j] = np.sum(x * y) / math.sqrt(np.sum(x * x) * np.sum(y * y))
    i, j = np.unravel_index(np.argmax(corr), corr.shape)
    assert 0 < i < corr.shape[0] - 1 and 0 < j < corr.shape[1] - 1, "peak on the edge"

    def vertex(m, c, p):
        return 0.5 * (m - p) / (m - 2 * c + p)

    dy = i - max_shift + vertex(corr[i - 1, j], corr[i, j], corr[i + 1, j])
    dx = j - max_shift + vertex(corr[i, j - 1], corr[i, j], corr[i, j + 1])
    return dx, dy


@pytest.mark.parametrize("direction,altitude", [
    (0.0, 0.0), (90.0, 0.0), (30.0, 0.0), (135.0, 0.0), (210.0, 5000.0), (300.0, 5000.0),
])
def test_layer_moves_with_its_wind_in_the_loop(direction, altitude):
    step = 3.0  # pixels per frame
    speed = step * DX / T
    cfg = _config(speed, direction, altitude)
    result = simulate(cfg, 4 * T, seed=11, progress=False, snapshot_every=1)
    snaps = result.snapshots[:, 0]
    a = math.radians(direction)
    expected = (step * math.cos(a), step * math.sin(a))  # (columns, rows)
    for k in range(2):
        dx, dy = _displacement(snaps[k], snaps[k + 1])
        # the parabolic fit on a sharp peak is good to ~0.1 px (a swapped axis or a
        # flipped sign is off by >= 1.5 px here)
        assert dx == pytest.approx(expected[0], abs=0.3), (dx, dy, expected)
        assert dy == pytest.approx(expected[1], abs=0.3), (dx, dy, expected)


def test_displacement_estimator_on_a_known_shift():
    # the test's own estimator on a random field shifted by whole pixels
    rng = np.random.default_rng(0)
    field = np.cumsum(np.cumsum(rng.standard_normal((70, 70)), axis=0), axis=1)
    a = field[10:58, 10:58]
    b = field[10 - 2:58 - 2, 10 - 3:58 - 3]  # b(x, y) = a(x - 3, y - 2)
    dx, dy = _displacement(a, b)
    assert dx == pytest.approx(3.0, abs=0.05) and dy == pytest.approx(2.0, abs=0.05)


@pytest.mark.parametrize("axis", [0, 1])
def test_direction_theta_sees_the_layer_at_x_plus_h_theta(axis):
    # DESIGN.md: direction theta sees phi(x + h theta); theta = (x, y) with x along
    # columns. A static layer at h, directions h theta = 4 whole pixels off axis along x
    # and along y: the off-axis pupil is the on-axis one displaced by -4 px on that axis
    h = 5000.0
    theta = 4 * DX / h * 648000.0 / math.pi  # arcsec
    cfg = _config(0.0, 0.0, h, FieldConfig(size=2 * theta, n_points=3))  # planes hold it
    off = [0.0, 0.0]
    off[axis] = theta
    result = simulate(cfg, 2 * T, seed=5, progress=False, snapshot_every=1,
                      snapshot_directions=np.array([[0.0, 0.0], off]))
    a, b = result.snapshots[0]
    dx, dy = _displacement(a, b)
    expected = (-4.0, 0.0) if axis == 0 else (0.0, -4.0)
    assert dx == pytest.approx(expected[0], abs=0.1) and dy == pytest.approx(expected[1], abs=0.1)
