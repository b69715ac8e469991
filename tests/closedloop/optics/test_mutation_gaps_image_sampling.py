"""closedloop.optics.image_sampling: the three sizes, from their documented definitions.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/optics/image_sampling.py").
References, from outside the code under test: each size recomputed here from the words
of its docstring, by search rather than by the module's closed form:

- the PSF's margin is ``4 lambda/d + max_shift + 1`` pixels rounded up (lambda/d
  converted here from radians to pixels with ``648000 / pi`` arcsec per radian), the
  support the first integer ``>= field + 2 margin`` whose prime factors are 2, 3 and 5
  only (found by trial division; the docstring's example: 134 -> 135);
- the pupil oversampling is the smallest ``q >= 1`` whose PSF period ``q lambda / du``
  [rad] is at least ``psf_pixels`` pixels;
- the PSF subsampling is the smallest ``s >= 1`` for which ``lambda / d`` spans at least
  2 samples of ``pixel / s`` (Nyquist).

Every case keeps its ratio at least 1e-3 from a whole number, so no assertion rests on
rounding.
"""

import math

import pytest

from closedloop.optics.image_sampling import (
    convolution_support,
    psf_subsampling,
    pupil_oversampling_needed,
)

ARCSEC = math.pi / 648_000.0


def _smooth(n):
    for p in (2, 3, 5):
        while n % p == 0:
            n //= p
    return n == 1


def _first_smooth(n):
    while not _smooth(n):
        n += 1
    return n


def _away_from_whole(x):
    assert abs(x - round(x)) > 1e-3, x  # the case is not on a rounding edge


def _margin(ps, d, lam, max_shift):
    lam_d = lam / d / ARCSEC / ps  # lambda/d [pixels]
    _away_from_whole(4 * lam_d)
    k = 0
    while k < 4 * lam_d:
        k += 1
    return k + max_shift + 1


@pytest.mark.parametrize(("field", "ps", "d", "lam", "max_shift"), [
    (24, 0.5, 0.25, 500e-9, 3),     # lambda/d = 0.825 px: margin 4 + 3 + 1 = 8, support 40
    (118, 0.5, 0.25, 500e-9, 3),    # 118 + 16 = 134 = 2 x 67 -> 135 (the docstring's case)
    (20, 0.25, 0.1, 630e-9, 5),     # lambda/d = 5.2 px: margin 21 + 5 + 1 = 27, 74 -> 75
    (33, 1.0, 0.7, 1.56e-6, 1),     # lambda/d = 0.46 px: margin 2 + 1 + 1 = 4, 41 -> 45
    (7, 0.5, 0.08, 500e-9, 2),      # lambda/d = 2.58 px: margin 11 + 2 + 1 = 14, 35 -> 36
])
def test_margin_and_support(field, ps, d, lam, max_shift):
    margin, support = convolution_support(field, ps, d, lam, max_shift)
    want = _margin(ps, d, lam, max_shift)
    assert (margin, support) == (want, _first_smooth(field + 2 * want))
    assert type(margin) is int and type(support) is int


def test_support_examples_by_hand():
    assert convolution_support(24, 0.5, 0.25, 500e-9, 3) == (8, 40)
    assert convolution_support(118, 0.5, 0.25, 500e-9, 3) == (8, 135)
    # an int-like float max_shift is taken as its int
    assert convolution_support(24, 0.5, 0.25, 500e-9, 3.0) == (8, 40)


def _q(psf_pixels, ps, du, lam):
    _away_from_whole(psf_pixels * ps * ARCSEC * du / lam)
    q = 1
    while q * lam / du < psf_pixels * ps * ARCSEC:  # the PSF repeats inside the support
        q += 1
    return q


@pytest.mark.parametrize(("psf_pixels", "ps", "du", "lam"), [
    (40, 0.5, 0.25 / 64, 500e-9),    # ratio 0.76: no oversampling needed, q = 1
    (16, 0.25, 0.1 / 8, 630e-9),     # 0.38 -> 1
    (40, 0.5, 0.25 / 16, 500e-9),    # 3.03 -> 4
    (135, 0.5, 0.25 / 16, 500e-9),   # 10.2 -> 11
    (75, 0.25, 0.1 / 8, 630e-9),     # 1.80 -> 2
    (200, 1.0, 0.05, 500e-9),        # 96.96 -> 97
    (64, 0.3, 0.02, 854e-9),         # 2.18 -> 3
])
def test_pupil_oversampling(psf_pixels, ps, du, lam):
    q = pupil_oversampling_needed(psf_pixels, ps, du, lam)
    assert q == _q(psf_pixels, ps, du, lam)
    assert type(q) is int


def _s(ps, d, lam):
    _away_from_whole(2 * ps * ARCSEC * d / lam)
    s = 1
    while lam / d < 2 * (ps * ARCSEC / s):  # lambda/d spans fewer than 2 samples
        s += 1
    return s


@pytest.mark.parametrize(("ps", "d", "lam"), [
    (0.5, 0.25, 500e-9),    # 2 x 0.5" / 0.41" = 2.4 -> 3
    (0.1, 0.25, 500e-9),    # 0.48 -> 1
    (0.25, 0.1, 630e-9),    # 0.38 -> 1
    (1.0, 0.7, 500e-9),     # 13.6 -> 14
    (0.3, 0.075, 400e-9),   # 0.55 -> 1
    (0.4, 0.4, 500e-9),     # 3.1 -> 4
])
def test_psf_subsampling(ps, d, lam):
    s = psf_subsampling(ps, d, lam)
    assert s == _s(ps, d, lam)
    assert type(s) is int
