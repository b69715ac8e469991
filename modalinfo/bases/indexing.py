"""Zernike index conventions: Noll, ANSI/OSA and Fringe (University of Arizona).

Every convention maps a single index to the radial order ``n >= 0`` and the signed
azimuthal frequency ``m`` with ``|m| <= n`` and ``n - |m|`` even. ``m > 0`` means a
``cos(m theta)`` mode and ``m < 0`` a ``sin(|m| theta)`` mode, as in ANSI/OSA.

- Noll (1976), ``j >= 1``: modes ordered by ``n``, then ``|m|``; for ``m != 0`` the even
  ``j`` is the cosine mode and the odd ``j`` the sine mode. ``j = 1`` is piston,
  ``j = 2, 3`` tip/tilt (x, y), ``j = 4`` defocus.
- ANSI/OSA (ISO 24157), ``j >= 0``: ``j = (n (n + 2) + m) / 2``.
- Fringe (University of Arizona / Code V), ``j >= 1``:
  ``j = (1 + (n + |m|) / 2)**2 - 2 |m| + (1 if m < 0 else 0)``, except that the 37th
  term is the 12th-order spherical aberration ``(12, 0)``, as in the 37-term Fringe set
  that Zemax and Code V export (``924 rho^12 - ...``), and ``(6, 6)``, which the group
  formula puts at 37, takes that formula's place of ``(12, 0)``, 49 (no standard goes
  beyond 37 terms; round 10 PART a: a 37-term export's last column read as a hexafoil).

All functions accept Python ints or integer arrays and return the same kind.
"""

from __future__ import annotations

import numbers
import re
import unicodedata
from typing import Any

import numpy as np

from modalinfo.common.validation import unmasked

__all__ = [
    "noll_to_zernike",
    "zernike_to_noll",
    "ansi_to_zernike",
    "zernike_to_ansi",
    "fringe_to_zernike",
    "zernike_to_fringe",
    "noll_to_ansi",
    "ansi_to_noll",
    "noll_to_fringe",
    "fringe_to_noll",
    "parse_modes",
]


#: Largest index converted, and largest radial order: the int64 arithmetic of the
#: conversions (``8 (j - 1) + 1``, ``n (n + 1)``, ``(q + 1)^2``) stays exact below 2^63
#: (j = 2^62 + 1 gave n = 4.6e18, m = -3.5e18, |m| > n, with a RuntimeWarning). Every
#: mode of radial order <= 2^29 (half a billion) has an index below 2^59 in all three
#: conventions, far beyond any sampled basis.
MAX_INDEX = 2**59
MAX_ORDER = 2**29
#: Most entries a mode list written as text may name (:func:`parse_modes`): one per
#: column of a log, 200 times the widest wavefront sensor (``telemetry.checks.MAX_MODES``).
#: ``--in-modes 2-1000000000000`` expanded its range first and ended in a MemoryError
#: ("use a smaller log"), and ``2-30000000`` held gigabytes (round 39 PART b, S34 / S42).
MAX_LISTED_MODES = 1_000_000


def _as_index(value: Any, name: str, minimum: int | None = None,
              maximum: int | None = None) -> tuple[np.ndarray, bool]:
    """Return ``value`` as an int64 array and whether it was a scalar."""
    if isinstance(value, bool | np.bool_):
        raise TypeError(f"`{name}` must be an int or an integer array; got {value!r}.")
    if isinstance(value, numbers.Integral):
        if maximum is not None and int(value) > maximum:
            raise ValueError(f"`{name}` must be <= {maximum}; got {int(value)}.")
        if not -(2**63) <= int(value) < 2**63:
            raise ValueError(f"`{name}` must fit in int64; got {int(value)}.")
        arr = np.asarray(int(value), dtype=np.int64)
        scalar = True
    else:
        arr = np.asarray(unmasked(value, name))
        if arr.size == 0 and arr.dtype.kind == "f":
            # an empty list or tuple is float64 to NumPy, not a float index: before
            # round 15 PART a (b42) `zernike_matrix([], ...)` was refused as "dtype
            # float64 and shape (0,)"; no index is given, so none is wrong
            arr = arr.astype(np.int64)
        if arr.dtype.kind not in "iu":  # timedelta64 counts as an integer in NumPy
            raise TypeError(
                f"`{name}` must be an int or an integer array; got dtype {arr.dtype}"
                + (f" with value {value!r}." if arr.ndim == 0 else f" and shape {arr.shape}.")
            )
        arr = arr.astype(np.int64)
        scalar = False
    if minimum is not None and arr.size and int(arr.min()) < minimum:
        bad = int(arr.min())
        raise ValueError(f"`{name}` must be >= {minimum}; got {bad}.")
    if maximum is not None and arr.size and int(arr.max()) > maximum:
        raise ValueError(f"`{name}` must be <= {maximum}; got {int(arr.max())}.")
    return arr, scalar


def _out(arr: np.ndarray, scalar: bool):
    return int(arr) if scalar else arr


def _check_nm(n: Any, m: Any) -> tuple[np.ndarray, np.ndarray, bool]:
    n_arr, n_scalar = _as_index(n, "n", minimum=0, maximum=MAX_ORDER)
    m_arr, m_scalar = _as_index(m, "m")
    try:
        n_arr, m_arr = np.broadcast_arrays(n_arr, m_arr)
    except ValueError as exc:
        raise ValueError(
            f"`n` and `m` must broadcast together; got shapes {n_arr.shape} and {m_arr.shape}."
        ) from exc
    bad = (np.abs(m_arr) > n_arr) | ((n_arr - np.abs(m_arr)) % 2 != 0)
    if np.any(bad):
        k = int(np.flatnonzero(bad.ravel())[0])
        raise ValueError(
            "`m` must satisfy |m| <= n with n - |m| even; "
            f"got n={int(n_arr.ravel()[k])}, m={int(m_arr.ravel()[k])}."
        )
    return n_arr.astype(np.int64), m_arr.astype(np.int64), n_scalar and m_scalar


def _isqrt(a: np.ndarray) -> np.ndarray:
    """Exact integer square root of a non-negative int64 array."""
    r = np.floor(np.sqrt(a.astype(np.float64))).astype(np.int64)
    r = np.where(r * r > a, r - 1, r)
    r = np.where((r + 1) * (r + 1) <= a, r + 1, r)
    return r


def noll_to_zernike(j):
    """Radial order and signed azimuthal frequency of Noll index ``j``.

    Parameters
    ----------
    j : int or array_like of int
        Noll index, ``j >= 1`` (``1`` is piston).

    Returns
    -------
    n, m : int or numpy.ndarray
        Radial order and signed azimuthal frequency (``m > 0`` cosine, ``m < 0`` sine),
        same shape as ``j``.

    Raises
    ------
    TypeError
        If ``j`` is not integer.
    ValueError
        If ``j < 1``.
    """
    jj, scalar = _as_index(j, "j", minimum=1, maximum=MAX_INDEX)
    n = (_isqrt(8 * (jj - 1) + 1) - 1) // 2
    p = jj - n * (n + 1) // 2
    k = n % 2
    m_abs = ((p + k) // 2) * 2 - k
    m = np.where(jj % 2 == 0, m_abs, -m_abs)
    return _out(n, scalar), _out(m, scalar)


def zernike_to_noll(n, m):
    """Noll index of the Zernike mode ``(n, m)``.

    Parameters
    ----------
    n : int or array_like of int
        Radial order, ``n >= 0``.
    m : int or array_like of int
        Signed azimuthal frequency, ``|m| <= n``, ``n - |m|`` even.

    Returns
    -------
    int or numpy.ndarray
        Noll index ``j >= 1``.
    """
    n_arr, m_arr, scalar = _check_nm(n, m)
    m_abs = np.abs(m_arr)
    base = n_arr * (n_arr + 1) // 2
    # The pair (cos, sin) of |m| occupies p = |m| and |m| + 1 (p = 1 for m = 0);
    # the even one of the two Noll indices is the cosine.
    j0 = base + np.maximum(m_abs, 1)
    want_even = m_arr >= 0
    is_even = j0 % 2 == 0
    j = np.where((m_arr == 0) | (is_even == want_even), j0, j0 + 1)
    return _out(j, scalar)


def ansi_to_zernike(j):
    """Radial order and signed azimuthal frequency of ANSI/OSA index ``j >= 0``.

    Parameters
    ----------
    j : int or array_like of int
        ANSI/OSA index, ``j >= 0`` (``0`` is piston).

    Returns
    -------
    n, m : int or numpy.ndarray
        Radial order and signed azimuthal frequency.
    """
    jj, scalar = _as_index(j, "j", minimum=0, maximum=MAX_INDEX)
    n = (_isqrt(8 * jj + 1) - 1) // 2
    m = 2 * jj - n * (n + 2)
    return _out(n, scalar), _out(m, scalar)


def zernike_to_ansi(n, m):
    """ANSI/OSA index ``(n (n + 2) + m) / 2`` of the mode ``(n, m)``.

    Parameters
    ----------
    n : int or array_like of int
        Radial order, ``n >= 0``.
    m : int or array_like of int
        Signed azimuthal frequency, ``|m| <= n``, ``n - |m|`` even.

    Returns
    -------
    int or numpy.ndarray
        ANSI/OSA index ``j >= 0``, same shape as the broadcast ``n``, ``m``.
    """
    n_arr, m_arr, scalar = _check_nm(n, m)
    return _out((n_arr * (n_arr + 2) + m_arr) // 2, scalar)


def fringe_to_zernike(j):
    """Radial order and signed azimuthal frequency of Fringe index ``j >= 1``.

    Parameters
    ----------
    j : int or array_like of int
        Fringe (University of Arizona) index, ``j >= 1`` (``1`` is piston, ``9`` the
        primary spherical aberration, ``37`` the 12th-order one: module notes).

    Returns
    -------
    n, m : int or numpy.ndarray
        Radial order and signed azimuthal frequency.
    """
    jj, scalar = _as_index(j, "j", minimum=1, maximum=MAX_INDEX)
    jj = _fringe_swap(jj)  # 37 is (12, 0) in the 37-term set (module notes)
    q = _isqrt(jj - 1)  # q = (n + |m|) / 2
    d = (q + 1) ** 2 - jj  # d = 2 |m| - (m < 0)
    m_abs = (d + 1) // 2
    m = np.where(d % 2 == 0, m_abs, -m_abs)
    n = 2 * q - m_abs
    return _out(n, scalar), _out(m, scalar)


def zernike_to_fringe(n, m):
    """Fringe index of the mode ``(n, m)``.

    Parameters
    ----------
    n : int or array_like of int
        Radial order, ``n >= 0``.
    m : int or array_like of int
        Signed azimuthal frequency, ``|m| <= n``, ``n - |m|`` even.

    Returns
    -------
    int or numpy.ndarray
        Fringe index ``j >= 1``, same shape as the broadcast ``n``, ``m``.
    """
    n_arr, m_arr, scalar = _check_nm(n, m)
    m_abs = np.abs(m_arr)
    j = (1 + (n_arr + m_abs) // 2) ** 2 - 2 * m_abs + (m_arr < 0)
    return _out(_fringe_swap(j.astype(np.int64)), scalar)


#: The 37-term Fringe set's last term, (12, 0), and the place the group formula gives it.
_FRINGE_37, _FRINGE_GROUP_12_0 = 37, 49


def _fringe_swap(j: np.ndarray) -> np.ndarray:
    """Exchange the indices 37 and 49 (an involution: the same map both ways)."""
    return np.where(j == _FRINGE_37, _FRINGE_GROUP_12_0,
                    np.where(j == _FRINGE_GROUP_12_0, _FRINGE_37, j))


def noll_to_ansi(j):
    """ANSI/OSA index of Noll index ``j >= 1``.

    Parameters
    ----------
    j : int or array_like of int
        Noll index, ``j >= 1``.

    Returns
    -------
    int or numpy.ndarray
        ANSI/OSA index of the same mode, same shape as ``j``.
    """
    return zernike_to_ansi(*noll_to_zernike(j))


def ansi_to_noll(j):
    """Noll index of ANSI/OSA index ``j >= 0``.

    Parameters
    ----------
    j : int or array_like of int
        ANSI/OSA index, ``j >= 0``.

    Returns
    -------
    int or numpy.ndarray
        Noll index of the same mode, same shape as ``j``.
    """
    return zernike_to_noll(*ansi_to_zernike(j))


def noll_to_fringe(j):
    """Fringe index of Noll index ``j >= 1``.

    Parameters
    ----------
    j : int or array_like of int
        Noll index, ``j >= 1``.

    Returns
    -------
    int or numpy.ndarray
        Fringe index of the same mode, same shape as ``j``.
    """
    return zernike_to_fringe(*noll_to_zernike(j))


def fringe_to_noll(j):
    """Noll index of Fringe index ``j >= 1``.

    Parameters
    ----------
    j : int or array_like of int
        Fringe index, ``j >= 1``.

    Returns
    -------
    int or numpy.ndarray
        Noll index of the same mode, same shape as ``j``.
    """
    return zernike_to_noll(*fringe_to_zernike(j))


#: Dashes a word processor or a keyboard layout types for '-' in a range ("2–6"): hyphen,
#: non-breaking hyphen, figure dash, en dash, em dash, horizontal bar, minus sign.
_OTHER_DASHES = "\u2010\u2011\u2012\u2013\u2014\u2015\u2212"


#: "Z2..Z7" / "2..7": the range spelling modalinfo's own notes print (describe_modes)
_DOTTED_RANGE = re.compile(r"(?P<p>[A-Za-z]*)(?P<a>[0-9]+)\s*\.\.\s*(?P<q>[A-Za-z]*)(?P<b>[0-9]+)")


def parse_modes(text: str, name: str = "modes") -> list[int] | list[str]:
    """Parse a mode list written as text, e.g. ``"2-28"``, ``"4,5,6"`` or ``"Z4,Z5"``.

    Parameters
    ----------
    text : str
        Comma-separated indices, inclusive ``a-b`` ranges of indices (also written
        ``a..b`` or ``Za..Zb``, as modalinfo's notes print them), or labels.
    name : str, optional
        What the errors call the text (an argument name, a command-line flag).

    Returns
    -------
    list of int or list of str
        The indices in the order given (ranges expanded), or the labels.

    Raises
    ------
    ValueError
        An empty entry, a decreasing range, indices mixed with labels, or more than
        ``MAX_LISTED_MODES`` (1,000,000) entries.
    """
    out: list = []
    for part in (p.strip() for p in text.split(",")):
        if not part:
            raise ValueError(f"{name}: empty entry in {text!r}")
        # isdecimal, not isdigit: superscripts are digits int() refuses ("invalid literal
        # for int()", no argument named); other scripts' decimal digits (Arabic-Indic,
        # full-width) are read as int() reads them (round 44 PART b a01; fixes 45-c, Y12)
        lo, sep, hi = part.partition("-")
        dotted = _DOTTED_RANGE.fullmatch(part)
        if dotted is not None:
            # the spelling modalinfo prints ("modes Z2..Z7 (noll) (assumed)") was one
            # label, "got 1 entry" (fix53-c, noticed): read it as the range 2-7
            if dotted["p"].upper() != dotted["q"].upper() or dotted["p"] not in ("", "Z", "z"):
                raise ValueError(f"{name}: {part!r} is read as a range of indices only as "
                                 f"'a..b' or 'Za..Zb'; write the indices, e.g. "
                                 f"'{dotted['a']}-{dotted['b']}', or list the labels")
            lo, sep, hi = dotted["a"], "-", dotted["b"]
            if int(hi) < int(lo):
                raise ValueError(f"{name}: range {part!r} is decreasing")
            part = f"{lo}-{hi}"
        dash = next((c for c in part if c in _OTHER_DASHES), None)
        if dash is not None and all(side.strip().isdecimal()
                                    for side in part.split(dash, 1)):
            raise ValueError(f"{name}: {part!r} joins mode indices with "
                             f"U+{ord(dash):04X} ({unicodedata.name(dash).lower()}), not a "
                             f"hyphen-minus: write {part.replace(dash, '-')!r}")
        bare = "".join(c for c in part if c != "-" and c not in _OTHER_DASHES)
        if bare.isdigit() and not bare.isdecimal():  # superscripts, circled digits
            odd = next(c for c in bare if not c.isdecimal())
            plain = "".join(str(unicodedata.digit(c)) if c.isdigit() else c for c in part)
            raise ValueError(f"{name}: {part!r} holds {odd!r} (U+{ord(odd):04X}, "
                             f"{unicodedata.name(odd, 'a digit').lower()}), a digit that is "
                             f"not read as a number: write {plain!r}")
        if sep and lo.isdecimal() and hi.isdecimal():
            if int(hi) < int(lo):
                raise ValueError(f"{name}: range {part!r} is decreasing")
            if len(out) + int(hi) - int(lo) + 1 > MAX_LISTED_MODES:
                raise ValueError(f"{name}: range {part!r} names {int(hi) - int(lo) + 1} modes; "
                                 f"a mode list names one mode per column of a log, at most "
                                 f"{MAX_LISTED_MODES}")
            out.extend(range(int(lo), int(hi) + 1))
        elif part.isdecimal():
            out.append(int(part))
        else:
            out.append(part)
    kinds = {type(x) for x in out}
    if len(kinds) > 1:
        raise ValueError(f"{name} mixes indices and labels: {text!r}")
    return out
