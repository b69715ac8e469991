"""``basis_for_log`` / ``compare_orderings`` from Python say what the theoretical K-L assumes.

Issue 27, left26-kde item 2. Left24-status made the command lines, ``batch`` and
``paper_figures --log`` say that a log without metadata gets an infinite outer scale
(Kolmogorov) and, for a finite one, a 1 m pupil; a Python caller of
``basis_for_log("kl-theory", log)`` or ``compare_orderings`` got the same assumption
without a word. References, outside the code: Kolmogorov vs von Karman turbulence
(Conan 2000: the K-L depends on the outer scale L0 and on D / L0, which a bare array
saved with numpy does not carry), and the one text of the CLI's note
(tests/cli/test_cli_round24.py, tests/batch/test_kl_assumed_left24.py). A call that
passes the geometry, or a log that records it, gets no warning; a warning names this
file (the caller), once per call.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from modalinfo.ordering.compare import KLGeometryWarning, basis_for_log, compare_orderings
from modalinfo.telemetry.log import ModalLog

KOLMOGOROV = ("no outer scale: the theoretical K-L assumes Kolmogorov turbulence "
              "(infinite outer scale; outer_scale= gives a von Karman one)")
ONE_METRE = "no pupil diameter: the von Karman K-L assumes D = 1 m"


def _log(**metadata) -> ModalLog:
    coeffs = np.random.default_rng(26).standard_normal((300, 5)) * 0.01
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad",
                    wavelength=5e-7, metadata=metadata)


def _caught(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()
    return [w for w in caught if issubclass(w.category, KLGeometryWarning)]


def test_bare_log_warns_once_at_the_caller():
    got = _caught(lambda: basis_for_log("kl-theory", _log(), n_pixels=16))
    assert len(got) == 1 and KOLMOGOROV in str(got[0].message)
    assert got[0].filename == __file__
    got = _caught(lambda: compare_orderings(_log(), "zernike:standard,kl-theory:variance",
                                            n_pixels=16))
    assert len(got) == 1 and KOLMOGOROV in str(got[0].message)
    assert got[0].filename == __file__


def test_finite_outer_scale_without_a_diameter_warns_the_one_metre_pupil():
    got = _caught(lambda: basis_for_log("kl-theory", _log(), n_pixels=16, outer_scale=20.0))
    assert len(got) == 1 and ONE_METRE in str(got[0].message)


@pytest.mark.parametrize("kwargs, metadata", [
    ({"outer_scale": math.inf}, {}),                    # Kolmogorov, said by the caller
    ({"outer_scale": 20.0, "diameter": 0.7}, {}),      # von Karman, both given
    ({}, {"outer_scale": 20.0, "diameter": 0.7}),      # recorded by the log
    ({"diameter": 0.7}, {"outer_scale": 20.0}),
])
def test_geometry_given_or_recorded_is_silent(kwargs, metadata):
    assert _caught(lambda: basis_for_log("kl-theory", _log(**metadata), n_pixels=16,
                                         **kwargs)) == []


def test_other_bases_assume_nothing():
    assert _caught(lambda: compare_orderings(_log(), "zernike:standard,kl-data:pca",
                                             n_pixels=16)) == []
