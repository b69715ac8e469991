"""Zernike index conventions.

References: Noll (1976) JOSA 66, 207, Table 1 (first 21 modes); the ANSI/OSA definition
j = (n (n + 2) + m) / 2 (ISO 24157, Thibos et al. 2002); the Fringe (University of
Arizona) table of Wyant & Creath (1992), Table 2 (first 36 terms); hcipy's independent
``noll_to_zernike`` / ``ansi_to_zernike`` as a second implementation; round trips;
for ``parse_modes``, lists written out by hand from its grammar.
"""

import hcipy
import hypothesis.strategies as st
import numpy as np
import pytest
from hypothesis import given

from modalinfo.bases import (
    ansi_to_noll,
    ansi_to_zernike,
    fringe_to_noll,
    fringe_to_zernike,
    noll_to_ansi,
    noll_to_fringe,
    noll_to_zernike,
    parse_modes,
    zernike_to_ansi,
    zernike_to_fringe,
    zernike_to_noll,
)

# Noll (1976) Table 1: Z1..Z21 (n, m); Noll writes cos for even j and sin for odd j,
# which we encode as m > 0 and m < 0.
NOLL_TABLE = [
    (0, 0), (1, 1), (1, -1), (2, 0), (2, -2), (2, 2), (3, -1), (3, 1), (3, -3), (3, 3),
    (4, 0), (4, 2), (4, -2), (4, 4), (4, -4), (5, 1), (5, -1), (5, 3), (5, -3), (5, 5),
    (5, -5),
]

# Wyant & Creath (1992), Table 2, Fringe Zernike terms 1..36 (cos -> m > 0, sin -> m < 0).
# (Term 37 of the Code V list is the special (12, 0) term outside the pattern.)
FRINGE_TABLE = [
    (0, 0), (1, 1), (1, -1), (2, 0), (2, 2), (2, -2), (3, 1), (3, -1), (4, 0), (3, 3),
    (3, -3), (4, 2), (4, -2), (5, 1), (5, -1), (6, 0), (4, 4), (4, -4), (5, 3), (5, -3),
    (6, 2), (6, -2), (7, 1), (7, -1), (8, 0), (5, 5), (5, -5), (6, 4), (6, -4), (7, 3),
    (7, -3), (8, 2), (8, -2), (9, 1), (9, -1), (10, 0),
]


def test_noll_table():
    for j, nm in enumerate(NOLL_TABLE, start=1):
        assert noll_to_zernike(j) == nm
        assert zernike_to_noll(*nm) == j


def test_noll_matches_hcipy():
    for j in range(1, 300):
        assert noll_to_zernike(j) == tuple(hcipy.noll_to_zernike(j))


def test_ansi_definition_and_hcipy():
    for j in range(0, 300):
        n, m = ansi_to_zernike(j)
        assert (n * (n + 2) + m) // 2 == j
        assert abs(m) <= n and (n - abs(m)) % 2 == 0
        assert (n, m) == tuple(hcipy.ansi_to_zernike(j))
    assert [ansi_to_zernike(j) for j in range(6)] == [
        (0, 0), (1, -1), (1, 1), (2, -2), (2, 0), (2, 2)
    ]


def test_fringe_table():
    for j, nm in enumerate(FRINGE_TABLE, start=1):
        assert fringe_to_zernike(j) == nm
        assert zernike_to_fringe(*nm) == j


def test_round_trips_arrays():
    j = np.arange(1, 1001)
    n, m = noll_to_zernike(j)
    assert n.shape == j.shape and n.dtype == np.int64
    np.testing.assert_array_equal(zernike_to_noll(n, m), j)
    np.testing.assert_array_equal(ansi_to_noll(noll_to_ansi(j)), j)
    np.testing.assert_array_equal(fringe_to_noll(noll_to_fringe(j)), j)
    a = np.arange(0, 1000)
    np.testing.assert_array_equal(noll_to_ansi(ansi_to_noll(a)), a)
    np.testing.assert_array_equal(zernike_to_ansi(*ansi_to_zernike(a)), a)
    np.testing.assert_array_equal(noll_to_fringe(fringe_to_noll(j)), j)
    # every (n, m) with n <= 20 appears exactly once in each convention
    n_all = np.concatenate([np.full(k + 1, k) for k in range(21)])
    m_all = np.concatenate([np.arange(-k, k + 1, 2) for k in range(21)])
    for to_j, start in ((zernike_to_noll, 1), (zernike_to_ansi, 0)):
        np.testing.assert_array_equal(
            np.sort(to_j(n_all, m_all)), np.arange(start, start + n_all.size)
        )
    assert len(set(zernike_to_fringe(n_all, m_all).tolist())) == n_all.size


@given(st.integers(min_value=1, max_value=10**9))
def test_round_trip_property(j):
    assert zernike_to_noll(*noll_to_zernike(j)) == j
    assert fringe_to_noll(noll_to_fringe(j)) == j
    assert ansi_to_noll(noll_to_ansi(j)) == j
    n, m = noll_to_zernike(j)
    assert abs(m) <= n and (n - abs(m)) % 2 == 0 and n * (n + 1) // 2 < j <= (n + 1) * (n + 2) // 2


def test_scalar_types():
    assert isinstance(noll_to_ansi(7), int)
    assert isinstance(noll_to_zernike(np.int32(7))[0], int)
    # Noll: even j cosine (m > 0), odd j sine (m < 0)
    j = np.arange(2, 500)
    _, m = noll_to_zernike(j)
    nz = m != 0
    assert np.all((m[nz] > 0) == (j[nz] % 2 == 0))


@pytest.mark.parametrize(
    ("func", "arg", "match"),
    [
        (noll_to_zernike, 0, r"`j` must be >= 1; got 0"),
        (noll_to_zernike, np.array([3, -2]), r"`j` must be >= 1; got -2"),
        (fringe_to_zernike, 0, r"`j` must be >= 1; got 0"),
        (noll_to_ansi, 0, r"`j` must be >= 1"),
        (fringe_to_noll, -1, r"`j` must be >= 1"),
        (ansi_to_zernike, -1, r"`j` must be >= 0; got -1"),
        (ansi_to_noll, -3, r"`j` must be >= 0"),
    ],
)
def test_bad_index(func, arg, match):
    with pytest.raises(ValueError, match=match):
        func(arg)


def test_bad_types_and_nm():
    with pytest.raises(TypeError, match="`j` must be an int or an integer array"):
        noll_to_zernike(2.0)
    with pytest.raises(TypeError, match="`j` must be an int"):
        noll_to_zernike(True)
    with pytest.raises(ValueError, match=r"\|m\| <= n with n - \|m\| even; got n=2, m=1"):
        zernike_to_noll(2, 1)
    with pytest.raises(ValueError, match=r"got n=1, m=3"):
        zernike_to_ansi(1, 3)
    with pytest.raises(ValueError, match="`n` must be >= 0"):
        zernike_to_fringe(-1, 0)


# ---------------------------------------------------------------- parse_modes
# Reference: the lists written out by hand from the documented grammar.
@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("2-5", [2, 3, 4, 5]),
        ("4, 2,7-8", [4, 2, 7, 8]),
        ("6-6", [6]),
        ("Z4,KL1", ["Z4", "KL1"]),
        ("tip-tilt", ["tip-tilt"]),  # not two digits: a label, not a range
    ],
)
def test_parse_modes(text, expected):
    assert parse_modes(text) == expected


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("2,,3", r"^modes: empty entry in '2,,3'$"),
        ("9-4", r"^modes: range '9-4' is decreasing$"),
        ("4,KL1", r"^modes mixes indices and labels: '4,KL1'$"),
    ],
)
def test_parse_modes_errors_name_the_argument(text, match):
    with pytest.raises(ValueError, match=match):
        parse_modes(text)
    with pytest.raises(ValueError, match=r"^--in-modes"):
        parse_modes(text, "--in-modes")


# --- adversarial round 5 (row b29): indices beyond int64's exact arithmetic -------------


def _noll_exact(j: int) -> tuple[int, int]:
    """Noll (1976) by Python's unbounded ints: n from the triangular numbers, m from p."""
    import math

    n = (math.isqrt(8 * (j - 1) + 1) - 1) // 2
    p = j - n * (n + 1) // 2
    m_abs = ((p + n % 2) // 2) * 2 - n % 2
    return n, m_abs if j % 2 == 0 else -m_abs


def test_the_largest_index_converts_exactly_and_one_more_is_refused():
    from modalinfo.bases.indexing import MAX_INDEX, MAX_ORDER

    for j in (MAX_INDEX, MAX_INDEX - 1):
        n, m = noll_to_zernike(j)
        assert (n, m) == _noll_exact(j) and abs(m) <= n
    for to_j, from_j in ((zernike_to_noll, noll_to_zernike), (zernike_to_ansi, ansi_to_zernike),
                         (zernike_to_fringe, fringe_to_zernike)):
        for m in (MAX_ORDER, -MAX_ORDER, 0):
            assert from_j(to_j(MAX_ORDER, m)) == (MAX_ORDER, m)
    for bad in (MAX_INDEX + 1, 2**62 + 1, 10**30):  # 2**62 + 1 gave |m| > n before
        for convert in (noll_to_zernike, ansi_to_zernike, fringe_to_zernike):
            with pytest.raises(ValueError, match="`j` must be <="):
                convert(bad)
    with pytest.raises(ValueError, match="`j` must be <="):
        noll_to_zernike(np.array([2, MAX_INDEX + 1]))
    with pytest.raises(ValueError, match="`n` must be <="):
        zernike_to_noll(3 * 10**9, 3 * 10**9)
