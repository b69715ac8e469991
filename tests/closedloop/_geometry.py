"""Field geometry written for the tests, independently of ``closedloop.optics.geometry``.

Reference: the hexagonal field set of the layer-oriented WFS (axial hexagonal
coordinates, rings of directions spaced ``field / 2 / (rings - 1)``) and the metapupil
of a layer at altitude ``h`` (diameter ``D + 2 h tan(field / 2)``), computed here on a
fine grid of each subaperture. One copy for the tests of the field-conjugated DM
(test_field_conjugated_dm_left27) and of the correlating SH's field rule
(test_correlating_field_rule_left29); not imported from the code under test.
"""

import math

import numpy as np

ARCSEC = math.pi / 648000.0


def hexagonal_directions(field: float, rings: int) -> np.ndarray:
    """The hexagonal field set: axial (q, r) with |q|, |r|, |q + r| < rings.

    Parameters
    ----------
    field : float
        Field of view [arcsec] (the outer ring's directions at ``field / 2``).
    rings : int
        Rings including the centre (>= 2).

    Returns
    -------
    numpy.ndarray, shape (3 rings (rings - 1) + 1, 2)
        Directions ``(x, y)`` [arcsec].
    """
    out = []
    for q in range(1 - rings, rings):
        for r in range(1 - rings, rings):
            if abs(q + r) < rings:
                out.append((q + 0.5 * r, r * math.sqrt(3.0) / 2.0))
    return np.array(out) * (field / 2.0) / (rings - 1)


def lit_fractions(diameter: float, altitude: float, field: float, rings: int, n_sub: int,
                  radius: float, fine: int) -> tuple[np.ndarray, np.ndarray]:
    """Fraction of each subaperture of the metapupil that each field direction lights.

    The telescope pupil (a disc of ``radius`` [m]) shifted by ``altitude theta`` for each
    direction ``theta`` of :func:`hexagonal_directions`, on a ``fine x fine`` grid of
    each of the ``n_sub x n_sub`` subapertures tiling the metapupil.

    Returns
    -------
    tuple
        ``(directions (n, 2) [arcsec], lit (n, n_sub^2))``, subapertures row-major
        (row = y, column = x).
    """
    d_wfs = diameter + 2.0 * altitude * math.tan(field / 2.0 * ARCSEC)
    pitch = d_wfs / n_sub
    off = ((np.arange(fine) + 0.5) / fine - 0.5) * pitch
    oy, ox = np.meshgrid(off, off, indexing="ij")
    centres = (np.arange(n_sub) + 0.5) * pitch - d_wfs / 2.0
    cy, cx = np.meshgrid(centres, centres, indexing="ij")  # row = y, column = x
    px = cx.ravel()[:, None] + ox.ravel()[None, :]
    py = cy.ravel()[:, None] + oy.ravel()[None, :]
    dirs = hexagonal_directions(field, rings)
    lit = np.array([(np.hypot(px - altitude * tx * ARCSEC, py - altitude * ty * ARCSEC)
                     <= radius).mean(axis=1) for tx, ty in dirs])
    return dirs, lit
