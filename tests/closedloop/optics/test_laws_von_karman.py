"""The FFT phase screens' von Karman roll-off against aotools' closed-form structure function.

Reference: ``aotools.turbulence.structure_function_vk`` (an outside library; the closed
form of e.g. Conan 2000, ``0.17253 (L0/r0)^(5/3) [1 - 2^(1/6) x^(5/6) K_5/6(x) /
Gamma(5/6)]``, ``x = 2 pi r / L0``). The quantity is
:func:`closedloop.optics.phase_screen.expected_structure_function`, the exact ensemble
structure function of the screens :func:`~closedloop.optics.phase_screen.fft_phase_screen`
draws (every lattice term, split cell, subharmonic and the tilt tail), so the check is
deterministic. With an outer scale of the order of the screen (here 0.5 and 1 m on a
4 m screen) the von Karman knee ``1 / L0`` lies in the FFT lattice beyond the
cell-integrated rings next to DC, where only the lattice's ``f^2 + 1 / L0^2`` sets it;
at the presets' L0 = 20 .. 27 m (and test_atmosphere.py's 25 m) the knee is inside those
rings and a wrong lattice term moves a screen's variance by 2e-7 only (256 pixels of
5 cm, L0 = 20 m, seed 0), under the golden tolerance. Measured ratios to
aotools, lags 1 .. 8 pixels: 0.9999 .. 1.0018 (L0 = 0.5 m), 0.9999 .. 1.0002 (1 m); with
the angular wavenumber ``(2 pi / L0)^2`` in place of ``1 / L0^2`` in the lattice:
0.856 .. 0.955 and 0.949 .. 0.992.
"""

import numpy as np
import pytest
from aotools.turbulence import structure_function_vk

from closedloop.optics.phase_screen import expected_structure_function


@pytest.mark.parametrize("outer_scale", [0.5, 1.0])
def test_small_outer_scale_structure_function_matches_aotools(outer_scale):
    g, dx, r0 = 64, 0.0625, 0.15
    lags = np.array([1, 2, 4, 8]) * dx
    ratio = (expected_structure_function(lags, g, dx, r0, outer_scale=outer_scale)
             / structure_function_vk(lags, r0, outer_scale))
    # within 0.5 %: measured <= 0.18 %; a 1 / L0 off by 2 pi moves the 1-pixel lag by 5-14 %
    np.testing.assert_allclose(ratio, 1.0, atol=5e-3)
