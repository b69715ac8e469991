"""Review20: the K-L note when the outer scale is given but the log has no diameter.

``reorder --outer-scale 20`` on a bare log (no metadata) builds a von Karman K-L whose
outer scale counts against a pupil of 1 m, the default of ``basis_for_log``'s
``diameter``. Reference, outside the note's code: the bases themselves. The K-L built
for the bare log equals the one built for the same log with ``diameter=1.0`` and
differs from the one with ``diameter=8.0`` (Conan 2000: the von Karman K-L depends on
L0 / D), so the note "assumes D = 1 m" is true and needed; with an infinite outer scale
(Kolmogorov, scale-free) or a recorded diameter nothing is assumed.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.ordering.compare import KLGeometryWarning, basis_for_log, kl_geometry_assumption
from modalinfo.telemetry import ModalLog

NO_DIAMETER = ("no pupil diameter: the von Karman K-L assumes D = 1 m (the outer scale "
               "counts relative to it)")


def _log(**metadata) -> ModalLog:
    coeffs = np.random.default_rng(20).standard_normal((200, 5))
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4, 5, 6], metadata=metadata)


def _kl(log, **kw) -> np.ndarray:
    return np.asarray(basis_for_log("kl-theory", log, n_pixels=16, **kw).variances)


def test_an_explicit_outer_scale_on_a_bare_log_says_d_is_1_m():
    bare = _log()
    # building it says the same thing as a warning (left26-kde's KLGeometryWarning)
    with pytest.warns(KLGeometryWarning, match="D = 1 m"):
        assumed = _kl(bare, outer_scale=20.0)
    assert np.allclose(assumed, _kl(bare, outer_scale=20.0, diameter=1.0))
    assert not np.allclose(assumed, _kl(bare, outer_scale=20.0, diameter=8.0), rtol=1e-2)
    assert kl_geometry_assumption(bare, outer_scale=20.0) == NO_DIAMETER


def test_nothing_assumed_with_a_diameter_or_an_infinite_outer_scale():
    assert kl_geometry_assumption(_log(), outer_scale=math.inf) is None
    assert kl_geometry_assumption(_log(diameter=8.0), outer_scale=20.0) is None
