"""Units of modal coefficients and the Zernike normalisation of the Fringe convention.

A log's coefficients are in one of four units:

``"rad"``
    wavefront phase in radians at the sensing wavelength ``lambda``;
``"waves"``
    the same phase in waves, ``waves = rad / (2 pi)``;
``"nm"``, ``"um"``
    optical path difference (OPD) in nanometres or micrometres.

The two families are linked by ``phase[rad] = 2 pi OPD / lambda`` and
``waves = OPD / lambda``, so converting between {rad, waves} and {nm, um} needs the
wavelength (metres). rad <-> waves and nm <-> um do not.

Fringe polynomials (University of Arizona ordering) are classically *peak*
normalised (``R_n^m(1) = 1``, no ``sqrt(n + 1)`` factor), whereas this package uses
unit-RMS Zernikes (Noll 1976) in every ordering. The same wavefront is
``a_rms Z_unit_rms = a_peak Z_peak`` with ``Z_unit_rms = N_nm Z_peak``, hence
``a_peak = N_nm a_rms`` where ``N_nm = sqrt(n + 1)`` for ``m = 0`` and
``sqrt(2 (n + 1))`` otherwise (:func:`zernike_rms_normalization`).
"""

from __future__ import annotations

import math

import numpy as np

from modalinfo.common.validation import check_choice, check_real, check_real_dtype, unmasked

__all__ = [
    "UNITS",
    "check_units",
    "check_wavelength",
    "WAVELENGTH_RANGE",
    "unit_scale",
    "zernike_rms_normalization",
    "rms_from_peak_normalized",
    "peak_normalized_from_rms",
]

#: The units a ``ModalLog`` can carry.
UNITS = ("rad", "nm", "um", "waves")

# Each unit expressed in its family's base: phase family base is rad, OPD base is metres.
_PHASE = {"rad": 1.0, "waves": 2.0 * math.pi}
_OPD = {"nm": 1e-9, "um": 1e-6}
#: Wavelengths [m] at which a phase (rad, waves) can be defined: the one rule of the API
#: (:func:`check_wavelength`) and of every command's ``--wavelength``. A wavefront sensor
#: or science camera works between the vacuum-UV edge and the far infrared: below about
#: 105 nm (the LiF cut-off) no lens, window or normal-incidence mirror coating of a
#: telescope transmits or reflects, so nothing shorter is sensed or corrected by a
#: deformable mirror (ground-based AO starts at ~300 nm, the ozone cut-off; solar AO at
#: 0.39 um, Ca II K); above the thermal infrared where AO ends (N and Q bands to ~25 um,
#: ELT METIS) the atmosphere is opaque to ~300 um and space telescopes there are
#: diffraction-limited without wavefront control. 100 nm - 100 um keeps a factor 3-4 of
#: margin at both ends; outside it a value is a unit slip (500 for 500 nm, 1.6 for 1.6 um,
#: 1e-30), and every phase <-> OPD conversion with it would be wrong by that factor.
WAVELENGTH_RANGE = (1e-7, 1e-4)
#: the range in words, for the refusals of the API and the command line
WAVELENGTH_RULE = ("100 nm - 100 um, the vacuum UV to the far infrared where a wavefront is "
                   "sensed; outside it the value is a unit slip such as nm typed as metres")


def check_units(units, name: str = "units") -> str:
    """Return ``units`` if it is one of :data:`UNITS`, else raise ``ValueError``."""
    if not isinstance(units, str):
        raise TypeError(f"`{name}` must be a str, one of {UNITS}; got {units!r}.")
    return check_choice(units, name, UNITS)


def check_wavelength(wavelength, name: str = "wavelength") -> float:
    """Return ``wavelength`` as a float in metres within :data:`WAVELENGTH_RANGE`, else raise.

    Parameters
    ----------
    wavelength : float
        Wavelength [m], in ``[1e-7, 1e-4]`` (100 nm - 100 um: why, at
        :data:`WAVELENGTH_RANGE`).
    name : str
        The argument's name in the refusal.

    Raises
    ------
    TypeError, ValueError
        Naming ``name``: not a real number, not finite, not > 0, or outside the range
        (the bounds catch a wavelength given in nanometres or micrometres).
    """
    lam = check_real(wavelength, name, minimum=0.0, strict_min=True)
    low, high = WAVELENGTH_RANGE
    if not low <= lam <= high:
        # a value just past a bound prints as the bound with 6 digits: give all of them;
        # the nm hint only for values a nanometre reading makes a wavelength (round 10 a)
        shown = f"{lam:g}" if not 0.999 * low <= lam <= 1.001 * high else repr(lam)
        slip = f" (did you mean {lam:g}e-9 m?)" if low <= lam * 1e-9 <= high else ""
        raise ValueError(f"`{name}` must be in metres within {low:g} - {high:g} "
                         f"({WAVELENGTH_RULE}); got {shown}{slip}.")
    return lam


def unit_scale(from_units: str, to_units: str, wavelength: float | None = None) -> float:
    """Return the factor ``f`` such that ``value[to_units] = f * value[from_units]``.

    Parameters
    ----------
    from_units, to_units : {"rad", "nm", "um", "waves"}
        Source and target units.
    wavelength : float, optional
        Wavelength in metres, in ``[1e-7, 1e-4]``, at which phase (rad, waves) is
        defined; required only when converting between the phase family (rad,
        waves) and OPD (nm, um).

    Returns
    -------
    float
        Multiplicative factor.

    Raises
    ------
    ValueError
        Unknown units, or a missing wavelength, or one outside 100 nm - 100 um, where
        one is needed.

    Examples
    --------
    500 nm of OPD at a 500 nm wavelength is one wave, or 2 pi rad:

    >>> round(500 * unit_scale("nm", "waves", 500e-9), 12)
    1.0
    """
    check_units(from_units, "from_units")
    check_units(to_units, "to_units")
    if from_units == to_units:
        return 1.0
    if (from_units in _PHASE) == (to_units in _PHASE):
        table = _PHASE if from_units in _PHASE else _OPD
        return table[from_units] / table[to_units]
    if wavelength is None:
        raise ValueError(
            f"`wavelength` (metres) is required to convert {from_units!r} to {to_units!r}; "
            "got None."
        )
    lam = check_wavelength(wavelength)
    if from_units in _PHASE:  # phase -> OPD: opd[m] = rad * lambda / (2 pi)
        metres = _PHASE[from_units] * lam / (2.0 * math.pi)
        return metres / _OPD[to_units]
    rad = _OPD[from_units] * 2.0 * math.pi / lam  # OPD -> phase
    return rad / _PHASE[to_units]


def zernike_rms_normalization(n, m):
    """Return the unit-RMS normalisation ``N_nm`` of the Zernike polynomial ``(n, m)``.

    ``N_nm = sqrt(n + 1)`` if ``m == 0`` else ``sqrt(2 (n + 1))`` (Noll 1976, eq. 4).

    Parameters
    ----------
    n : int or array_like of int
        Radial order.
    m : int or array_like of int
        Signed azimuthal frequency.

    Returns
    -------
    float or numpy.ndarray
        The factor(s).

    Raises
    ------
    TypeError, ValueError
        If ``n``, ``m`` are not integers with ``n >= 0``, ``|m| <= n``, ``n - |m|`` even
        (the check of the index converters in ``modalinfo.bases.indexing``).
    """
    from modalinfo.bases.indexing import _check_nm  # lazy: modalinfo.bases imports scipy

    n, m, _ = _check_nm(n, m)
    out = np.sqrt(np.where(m == 0, 1.0, 2.0) * (n + 1.0))
    return float(out) if out.ndim == 0 else out


def _fringe_factors(modes) -> np.ndarray:
    from modalinfo.bases import fringe_to_noll, noll_to_zernike
    from modalinfo.bases.indexing import _as_index

    # the index rule of the converters: 2.5 was truncated to 2, '4' parsed, 1+1j cast
    modes, scalar = _as_index(modes, "modes")
    if scalar or modes.ndim != 1 or modes.size == 0 or np.any(modes < 1):
        raise ValueError(f"`modes` must be a 1-D list of Fringe indices >= 1; got {modes!r}.")
    n, m = noll_to_zernike(fringe_to_noll(modes))
    return np.atleast_1d(zernike_rms_normalization(n, m))


def _fringe_coeffs(coeffs, n_modes: int) -> tuple[np.ndarray, type]:
    """``coeffs`` checked as real (T, M) or (M,) with M = ``n_modes``, and its float dtype.

    A floating input keeps its dtype (float32 stays float32); integers become float64.
    Complex, object, date and masked arrays are refused (the imaginary part was dropped
    or an object array returned), as is a last axis other than ``n_modes`` (one mode's
    (T,) series broadcast as T modes of one frame).
    """
    arr = np.asarray(unmasked(coeffs, "coeffs"))
    check_real_dtype(arr, "coeffs", coeffs)
    one_mode_series = arr.ndim == 1 and n_modes == 1  # (T,): the same numbers either way
    if arr.ndim not in (1, 2) or (arr.shape[-1] != n_modes and not one_mode_series):
        raise ValueError(f"`coeffs` must have shape (T, {n_modes}) or ({n_modes},) for "
                         f"{n_modes} mode(s); got {arr.shape}.")
    return arr, (arr.dtype.type if arr.dtype.kind == "f" else np.float64)


def rms_from_peak_normalized(coeffs, modes):
    """Convert coefficients of peak-normalised Fringe polynomials to unit-RMS ones.

    Parameters
    ----------
    coeffs : array_like, shape (T, M) or (M,)
        Coefficients of classical (peak-normalised) Fringe polynomials, any units.
    modes : sequence of int, length M
        Fringe indices (1 = piston) of the columns.

    Returns
    -------
    numpy.ndarray
        Coefficients of the unit-RMS polynomials of the same Fringe indices,
        ``a_rms = a_peak / N_nm``, same dtype as a floating input.
    """
    factors = _fringe_factors(modes)
    arr, dtype = _fringe_coeffs(coeffs, factors.size)
    return arr / factors.astype(dtype)


def peak_normalized_from_rms(coeffs, modes):
    """Convert unit-RMS Zernike coefficients (Fringe order) to peak-normalised Fringe ones.

    Inverse of :func:`rms_from_peak_normalized`: ``a_peak = N_nm a_rms``.

    Parameters
    ----------
    coeffs : array_like, shape (T, M) or (M,)
        Coefficients of unit-RMS Zernikes, columns in Fringe order.
    modes : sequence of int, length M
        Fringe indices (1 = piston) of the columns.

    Returns
    -------
    numpy.ndarray
        Peak-normalised Fringe coefficients.
    """
    factors = _fringe_factors(modes)
    arr, dtype = _fringe_coeffs(coeffs, factors.size)
    return arr * factors.astype(dtype)
