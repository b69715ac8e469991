"""Karhunen-Loeve modes in the space of a deformable mirror (DM-space K-L).

The modes a DM of actuators is controlled through, as OOPAO
(``OOPAO.calibration.compute_KL_modal_basis.compute_KL_basis`` -> ``compute_M2C``, the
"double diagonalisation" of Gendron 1995, also OOMAO's ``KLBasisDecomposition``) and
COMPASS (``shesha.ao.basis.compute_KL2V``) build them:

1. **Geometric diagonalisation** -- the DM metric. With ``M`` the influence functions
   on the ``n`` pupil pixels (``(n, n_act)``, :class:`~modalinfo.bases.InfluenceFunctions`),
   the Gram matrix ``G = M^T M / n`` is the pupil-mean inner product of mirror shapes;
   ``G = L L^T`` (Cholesky) whitens it: ``z = L^T c`` are coordinates in which mirror
   shapes are orthonormal.
2. **Statistical diagonalisation** -- the turbulence prior. The least-squares fit of a
   phase ``phi`` by the mirror has whitened coordinates ``z = L^{-1} M^T phi / n``,
   whose covariance is ``C_z = L^{-1} S L^{-T}``, ``S = M^T C_phi M / n^2``. ``C_phi``
   is the piston-removed von Karman covariance over the pupil,
   ``C_phi = -1/2 P D P`` with ``D[p, q] = D_phi(|x_p - x_q|)`` the phase structure
   function and ``P = I - 1 1^T / n`` the pupil-piston remover (the constant
   ``B(0)`` of the covariance, infinite for Kolmogorov turbulence, cancels in ``P``).
3. **Piston removed, tip/tilt apart.** The mirror's best fits of piston, ``x`` and
   ``y`` (``b = L^{-1} M^T t / n``) are orthonormalised in that order (Gram-Schmidt):
   the second and third vectors are **exactly the DM's best tip and tilt** (made
   piston-free) and become modes 1 and 2; piston is dropped; ``C_z`` is diagonalised
   in the orthogonal complement of the three, and its eigenvectors, by decreasing
   eigenvalue, are modes 3, 4, ... (With ``tip_tilt_apart=False`` only piston is
   removed and every mode is an eigenvector, as the library's theoretical K-L.)
   The modes' commands are ``M2C = L^{-T} [u_1 .. u_M]`` ``(n_act, M)``; their
   surfaces are orthonormal over the pupil (``M2C^T G M2C = I``), have zero pupil mean,
   and modes >= 3 have zero tip/tilt content. Tip/tilt keep their correlation with the
   coma-like modes (turbulence correlates Z2 and Z8): only the block of modes >= 3 is
   diagonal under the prior.

No ``(pixels x pixels)`` matrix is formed. The influence functions are separable,
``IF_a(x, y) = F[x, ax] F[y, ay]``, and ``D`` depends on the pixel lag only, so between
two actuators the pupil leaves whole (their support inside the mask)
``(M^T D M)[a, b] = sum_lx sum_ly c[ax, bx](lx) c[ay, by](ly) D(lx, ly)`` with the 1-D
correlations ``c[i, j]`` of the factor's columns (``n_across^2`` vectors of ~40 lags):
~``W`` multiply-adds per pair after a contraction along y per pair of actuator rows, no
FFT (``_dm_kl_kernels``). Each actuator the rim (or an obscuration) cuts takes one FFT
pair of its masked influence function on its support window (``D`` is Toeplitz on the
pixel grid, so ``D M`` is a convolution with ``D_phi`` on the ``(2N - 1)^2`` lags), one
per orbit of the pupil's symmetries (a centred disc: the flips of ``x`` and ``y`` and
their exchange, 8 cut actuators per transform; the others copy its column, permuted). The
complement of piston/tip/tilt is taken with their 1-3 Householder reflectors in the
whitened space (no ``n x n`` orthogonal matrix). At 4,553 actuators on a 298-pixel
altitude plane (948 of them cut) the projection takes ~9 s of CPU and the whole build
~28 s, most of it the eigen-decomposition (``benchmarks/RESULTS.md``, "DM-space K-L
without FFTs").

Structure function (von Karman; the closed form of the PSD's Hankel transform, e.g.
Conan 2000, PhD thesis, Universite Paris XI; the tests check it against the integral)::

    D_phi(r) = 2 (B(0) - B(r)),
    B(r) = (L0/r0)^(5/3) 2^(-5/6) Gamma(11/6) / pi^(8/3) [24/5 Gamma(6/5)]^(5/6)
           (2 pi r / L0)^(5/6) K_{5/6}(2 pi r / L0),
    B(0) = (L0/r0)^(5/3) Gamma(11/6) Gamma(5/6) / (2 pi^(8/3)) [24/5 Gamma(6/5)]^(5/6)
         = 0.0863 (L0/r0)^(5/3),

and ``D_phi(r) = 6.8839 (r/r0)^(5/3)`` for ``L0 = inf`` (Kolmogorov), its limit for
``r << L0``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import fft as sfft
from scipy import linalg, special

from modalinfo.bases import _dm_kl_cache, _dm_kl_kernels
from modalinfo.bases.basis import ModalBasis
from modalinfo.bases.influence import InfluenceFunctions
from modalinfo.common.validation import as_float_array, check_int, check_real

__all__ = ["DMKLBasis", "KOLMOGOROV_D_CONSTANT", "dm_kl_modes", "von_karman_structure_function"]

#: 2 [(24/5) Gamma(6/5)]^(5/6) = 6.8839 (Fried 1966): the Kolmogorov structure-function
#: constant, the project's one copy (closedloop.theory imports it). The expression as
#: evaluated in double precision, 6.88387718229381, one unit in the last place below the
#: correctly rounded 6.883877182293811 (math.gamma's rounding); kept so, since every DM
#: K-L basis and the presets' numbers rest on these bits.
KOLMOGOROV_D_CONSTANT = 2.0 * (24.0 / 5.0 * math.gamma(6.0 / 5.0)) ** (5.0 / 6.0)
_VK_B = (2.0 ** (-5.0 / 6.0) * math.gamma(11.0 / 6.0) / math.pi ** (8.0 / 3.0)
         * (24.0 / 5.0 * math.gamma(6.0 / 5.0)) ** (5.0 / 6.0))
_VK_B0 = (math.gamma(11.0 / 6.0) * math.gamma(5.0 / 6.0) / (2.0 * math.pi ** (8.0 / 3.0))
          * (24.0 / 5.0 * math.gamma(6.0 / 5.0)) ** (5.0 / 6.0))
#: MRRR (a subset of eigenpairs) is used below dim / _MRRR_SHARE wanted eigenpairs, divide
#: and conquer (all of them) above: the two cost the same near a third (measured at 1,581)
_MRRR_SHARE = 3
#: actuators per FFT batch (memory ~ batch x P^2 x 16 bytes: 60 MB at P = 343)
_BATCH = 32


def von_karman_structure_function(r, r0: float, outer_scale: float = np.inf) -> np.ndarray:
    """Phase structure function of von Karman turbulence [rad^2].

    Parameters
    ----------
    r : array_like
        Separations [m], any sign: ``D_phi`` is even, so ``r`` and ``-r`` (a shift
        component along either direction, as ``closedloop.theory.structure_function``
        passes) give ``D_phi(|r|)``.
    r0 : float
        Fried parameter [m] at the phase's wavelength, ``> 0``.
    outer_scale : float
        Outer scale ``L0`` [m], ``> 0``; ``inf`` for Kolmogorov ``6.8839 (r/r0)^(5/3)``.

    Returns
    -------
    numpy.ndarray
        ``D_phi(r)``, the shape of ``r`` (module docstring for the formula).
    """
    r0 = check_real(r0, "r0", minimum=0.0, strict_min=True)
    outer_scale = check_real(outer_scale, "outer_scale", minimum=0.0, strict_min=True,
                             allow_inf=True)
    # complex, date, string and masked separations were cast silently (audit 9)
    r = np.abs(as_float_array(r, "r"))
    if math.isinf(outer_scale):
        return KOLMOGOROV_D_CONSTANT * (r / r0) ** (5.0 / 3.0)
    u = 2.0 * math.pi * r / outer_scale
    small = (u < _VK_SERIES_U) & (u > 0)
    out = np.zeros_like(u)
    large = ~small & (u > 0)  # u = 0: D = 0 exactly, as B0 - b(0) = 0
    if large.any():
        try:
            scale = (outer_scale / r0) ** (5.0 / 3.0)
        except OverflowError:  # L0 / r0 beyond 1e184: only r ~ L0 lands here
            scale = math.inf
        ul = u[large]
        out[large] = 2.0 * scale * (_VK_B0 - _VK_B * ul ** (5.0 / 6.0) * special.kv(5.0 / 6.0, ul))
    if small.any():
        out[small] = 2.0 * (2.0 * math.pi * r[small] / r0) ** (5.0 / 3.0) * _vk_series(u[small])
    return out


#: Below this u = 2 pi r / L0 the difference B0 - b(u) of the closed form cancels (it is
#: ~u^(5/3): relative error eps / u^(5/3), 2000x too large a D at L0 = 1e10 m, r = 1 cm;
#: an OverflowError at L0 = 1e300); the series of :func:`_vk_series` is used instead.
#: At 1e-4 the closed form is still good to ~1e-9 and the presets' pixel lags
#: (u >= 2 pi x 1.5 cm / 50 m ~ 2e-3) keep their bits.
_VK_SERIES_U = 1e-4


def _vk_series(u: np.ndarray) -> np.ndarray:
    """``(B0 - b(u)) / u^(5/3)`` for small u, without cancellation.

    With ``nu = 5/6`` and ``u^nu K_nu(u) = pi / (2 sin(nu pi)) [u^nu I_-nu(u) - u^nu I_nu(u)]``
    (Abramowitz & Stegun 9.6.2), the constant term of ``u^nu I_-nu`` is ``B0 / B``; the rest
    are the power series 9.6.10, summed here to k = 3 ((u/2)^8 < 1e-35 below 1e-4).
    """
    nu = 5.0 / 6.0
    c = _VK_B * math.pi / (2.0 * math.sin(nu * math.pi))
    h = u / 2.0
    pos = sum(2.0 ** (-nu) * h ** (2 * k) / (math.factorial(k) * math.gamma(k + nu + 1))
              for k in range(4))
    neg = sum(2.0 ** (-nu) * h ** (2 * k - 2.0 * nu) / (math.factorial(k) * math.gamma(k - nu + 1))
              for k in range(1, 4))
    return c * (pos - neg)


def _lag_table(lags: np.ndarray, dx: float, r0: float, outer_scale: float) -> np.ndarray:
    """``D_phi`` at the pixel lags ``(lags[i], lags[j]) dx``: ``(len(lags), len(lags))``.

    Evaluated on one quadrant of ``|lag|`` and read back for the signs (``D`` depends on
    ``hypot(|lx| dx, |ly| dx)`` only, the same number as at the signed lags): the Bessel
    function is taken 4x less often, the same bits as the whole table.
    """
    a = np.abs(np.asarray(lags, dtype=np.int64))
    q = np.arange(a.max() + 1) * dx
    quadrant = von_karman_structure_function(np.hypot(q[:, None], q[None, :]), r0, outer_scale)
    return quadrant[np.ix_(a, a)]


def _whole_actuators(influence: InfluenceFunctions) -> np.ndarray:
    """Which valid actuators the pupil leaves whole: ``(n_valid,)`` bool.

    An actuator is whole when the rectangle its separable influence function is non-zero
    on (the factor's support along x times along y, clipped to the grid) lies inside the
    pupil's mask: its masked influence function is then still the outer product of two
    columns of the 1-D factor.
    """
    mask = np.asarray(influence.pupil.mask)
    lo, hi = _factor_support(influence.factor)
    n_across = influence.n_actuators
    grid = influence.valid_index
    ay, ax = grid // n_across, grid % n_across
    # summed-area table: the count of mask pixels in any rectangle in O(1)
    area = np.zeros((mask.shape[0] + 1, mask.shape[1] + 1), dtype=np.int64)
    area[1:, 1:] = np.cumsum(np.cumsum(mask, axis=0), axis=1)
    y0, y1, x0, x1 = lo[ay], hi[ay] + 1, lo[ax], hi[ax] + 1
    inside = area[y1, x1] - area[y0, x1] - area[y1, x0] + area[y0, x0]
    return inside == (y1 - y0) * (x1 - x0)


def _factor_support(factor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """First and last pixel of each column's non-zero support (``0, 0`` for a zero column)."""
    nonzero = factor != 0.0
    any_ = nonzero.any(axis=0)
    lo = np.where(any_, np.argmax(nonzero, axis=0), 0).astype(np.int64)
    hi = np.where(any_, factor.shape[0] - 1 - np.argmax(nonzero[::-1], axis=0),
                  0).astype(np.int64)
    return lo, hi


def _symmetries(influence: InfluenceFunctions) -> list[np.ndarray]:
    """Permutations of the valid actuators under the grid symmetries the problem keeps.

    The pixel grid and the actuator grid are both centred on the axis, so a flip of
    ``x``, of ``y`` or their exchange maps the pixel grid, the actuator sites and ``D``
    (a function of ``|lag|``) onto themselves. When it also maps the pupil's mask and the
    valid actuators onto themselves and the 1-D factor is exactly symmetric
    (``F[n-1-i, N-1-a] == F[i, a]``, as it is for the centred grids:
    :class:`~modalinfo.bases.InfluenceFunctions`), actuator ``a``'s masked influence
    function goes to that of ``perm[a]``, and ``(M^T D M)[perm[b], perm[a]] =
    (M^T D M)[b, a]``. Returns the ``perm`` of each such symmetry but the identity (up
    to 7; none for an asymmetric pupil, which then takes every column itself).
    """
    mask = np.asarray(influence.pupil.mask)
    factor = influence.factor
    if mask.shape[0] != mask.shape[1] or not np.array_equal(factor, factor[::-1, ::-1]):
        return []
    n_across = influence.n_actuators
    valid = influence.valid.reshape(n_across, n_across)
    index = np.full(n_across * n_across, -1, dtype=np.int64)
    index[influence.valid_index] = np.arange(influence.n_valid)
    index = index.reshape(n_across, n_across)
    perms = []
    for swap in (False, True):
        for flip_y in (False, True):
            for flip_x in (False, True):
                if not (swap or flip_y or flip_x):
                    continue

                def move(a, swap=swap, flip_y=flip_y, flip_x=flip_x):
                    a = a.T if swap else a
                    a = a[::-1] if flip_y else a
                    return a[:, ::-1] if flip_x else a

                if not (np.array_equal(move(mask), mask) and np.array_equal(move(valid), valid)):
                    continue
                # the site at move's source of (i, j) lands on (i, j)
                perm = np.empty(influence.n_valid, dtype=np.int64)
                perm[move(index)[valid]] = index[valid]
                perms.append(perm)
    return perms


def _separable_block(influence: InfluenceFunctions, r0: float, outer_scale: float,
                     members: np.ndarray, g_d: np.ndarray) -> None:
    """``M^T D M`` of the whole actuators ``members`` written into ``g_d`` (both triangles).

    ``sum_lx sum_ly c_x(lx) c_y(ly) D(lx, ly)`` with the 1-D correlations of the factor's
    columns (``_dm_kl_kernels``): ~``W`` multiply-adds per pair and ``W (2N + 2W)`` per
    pair of actuator rows, no FFT.
    """
    factor = np.ascontiguousarray(influence.factor)
    n_pix, n_across = factor.shape
    lo, hi = _factor_support(factor)
    width = int(2 * (hi - lo + 1).max() - 1)
    corr = np.empty((n_across, n_across, width))
    lag0 = np.empty((n_across, n_across), dtype=np.int64)
    _dm_kl_kernels.factor_correlations(factor, lo, hi, width, corr, lag0)
    # D at every pixel lag a pair can read, the zero-padded correlations' lags included
    centre = n_pix - 1 + width
    table = _lag_table(np.arange(-centre, centre + 1), influence.pixel_scale, r0, outer_scale)
    grid = influence.valid_index[members]
    gy, gx = grid // n_across, grid % n_across
    order = np.lexsort((gx, gy))  # by grid row, then column
    group_rows, row_start = np.unique(gy[order], return_index=True)
    row_start = np.append(row_start, members.size).astype(np.int64)
    _dm_kl_kernels.separable_projection(
        corr, lag0, table, centre, np.ascontiguousarray(gx[order]),
        group_rows.astype(np.int64), row_start, np.ascontiguousarray(members[order]),
        np.empty(2 * centre + 1), g_d)


def _structure_operator(influence: InfluenceFunctions, r0: float, outer_scale: float,
                        separable: bool = True):
    """``(G_D, u, v, s)`` for ``M^T D M``, ``M^T 1``, ``M^T D 1 / n``, ``1^T D 1 / n^2``.

    ``M^T D M``: between two actuators the pupil leaves whole (their influence functions
    unmasked, hence separable) from 1-D correlations of the factor
    (:func:`_separable_block`, no FFT); the column of each actuator the pupil's edge cuts
    by one FFT pair of its masked influence function with ``D`` on the grid's lags.
    A cut actuator that a symmetry of the problem (:func:`_symmetries`: the flips and
    the exchange of ``x`` and ``y`` of a centred disc) maps onto one already computed
    takes that column, permuted: one FFT pair per orbit, ~8x fewer on a disc
    (``benchmarks/RESULTS.md``, "The full-size est-mcao set-up under 60 s").
    ``separable=False`` takes the FFT column for every actuator, no symmetry (the
    reference the tests compare with, and what the build did before the separable path:
    45 s of the 66 s set-up of a 4,553-actuator altitude DM whose pitch is not a whole
    number of pixels, ``benchmarks/RESULTS.md``).
    """
    pupil = influence.pupil
    n_side = pupil.n_pixels
    mask = np.asarray(pupil.mask)
    flat = np.flatnonzero(mask.ravel())
    rows, cols = flat // n_side, flat % n_side
    n = flat.size
    dx = influence.pixel_scale
    mat = influence.matrix
    csc = mat.tocsc()
    n_act = mat.shape[1]
    g_d = np.empty((n_act, n_act))

    size = sfft.next_fast_len(2 * n_side - 1, real=True)
    lag = np.arange(size)
    lag = np.where(lag < n_side, lag, lag - size)  # wrapped lags
    kernel = sfft.rfft2(_lag_table(lag, dx, r0, outer_scale))

    whole_ = _whole_actuators(influence) if separable else np.zeros(n_act, dtype=bool)
    members = np.flatnonzero(whole_)
    edge = np.flatnonzero(~whole_)
    if members.size:
        _separable_block(influence, r0, outer_scale, members, g_d)
    # one cut actuator per orbit of the symmetries takes the transforms; the rest of its
    # orbit (cut too: the symmetries keep the mask and the supports) copies its column
    perms = _symmetries(influence) if separable else []
    images_of = {}
    if perms:
        seen = np.zeros(n_act, dtype=bool)
        computed = []
        for a in edge:
            if seen[a]:
                continue
            computed.append(a)
            seen[a] = True
            for perm in perms:
                b = int(perm[a])
                if not seen[b]:
                    seen[b] = True
                    images_of.setdefault(int(a), []).append((b, perm))
        transformed = np.array(computed, dtype=np.int64)
    else:
        transformed = edge
    # each cut actuator's image is non-zero in a (2 reach + 2)^2 window only: its
    # forward transform runs along x on the window's rows and along y with the shift
    # theorem, and the inverse along x only on the N rows read (~1/3 less than two
    # full 2-D transforms)
    pos = (influence.valid_positions - influence.coords[0]) / dx  # (column, row) pixels
    whole = np.floor(pos + 1e-9).astype(np.int64)
    reach = int(math.ceil(influence.radius / dx))
    side = 2 * reach + 2
    pad = side
    ky = np.fft.fftfreq(size)[None, :, None]
    kx = np.fft.rfftfreq(size)[None, None, :]
    images = np.zeros((_BATCH, n_side + 2 * pad, n_side + 2 * pad))
    for start in range(0, transformed.size, _BATCH):
        chunk = transformed[start:start + _BATCH]
        b = chunk.size
        images[:b] = 0.0
        images[np.arange(b)[:, None], rows[None, :] + pad,
               cols[None, :] + pad] = csc[:, chunk].toarray().T
        x0 = whole[chunk, 0] - reach  # window origin on the grid (may be < 0)
        y0 = whole[chunk, 1] - reach
        windows = np.stack([images[k, y0[k] + pad:y0[k] + pad + side,
                                   x0[k] + pad:x0[k] + pad + side] for k in range(b)])
        spec = sfft.rfft(windows, n=size, axis=2)
        spec *= np.exp(-2j * np.pi * kx * x0[:, None, None])
        spec = sfft.fft(spec, n=size, axis=1)
        spec *= np.exp(-2j * np.pi * ky * y0[:, None, None])
        spec *= kernel
        rows_ = sfft.ifft(spec, axis=1, overwrite_x=True)[:, :n_side, :]
        full = sfft.irfft(rows_, n=size, axis=2)[:, :, :n_side]
        g_d[:, chunk] = mat.T @ full.reshape(b, -1)[:, flat].T
    for a, images in images_of.items():
        for b, perm in images:
            g_d[perm, b] = g_d[:, a]
    u = np.asarray(mat.sum(axis=0)).ravel()
    spec = sfft.rfft2(mask.astype(np.float64), s=(size, size)) * kernel
    d_w = sfft.irfft2(spec, s=(size, size))[:n_side, :n_side].ravel()[flat] / n
    v = mat.T @ d_w
    s = float(d_w.sum() / n)
    if members.size and edge.size:  # the cut columns' whole rows give their transposes
        g_d[np.ix_(edge, members)] = g_d[np.ix_(members, edge)].T
    cut = g_d[np.ix_(edge, edge)]
    g_d[np.ix_(edge, edge)] = 0.5 * (cut + cut.T)
    return g_d, u, v, s


def _command_prior(influence: InfluenceFunctions, r0: float, outer_scale: float) -> np.ndarray:
    """``S = M^T C_phi M / n^2`` [rad^2], the prior covariance of ``M^T phi / n``."""
    n = influence.pupil.n_valid
    g_d, u, v, s = _structure_operator(influence, r0, outer_scale)
    # M^T C_phi M with C_phi = -1/2 P D P, P = I - 1 1^T / n
    s_mat = -0.5 * (g_d - np.outer(u, v) - np.outer(v, u) + s * np.outer(u, u)) / n**2
    return 0.5 * (s_mat + s_mat.T)


#: Accepted D / r0 of :func:`dm_kl_modes`: far beyond any telescope (D / r0 of 1e-3 to 1e4)
#: and within float64 once raised to 5/3 and squared by the eigensolver
_D_OVER_R0 = (1e-60, 1e60)


def dm_kl_modes(influence: InfluenceFunctions, r0: float, outer_scale: float = np.inf, *,
                n_modes: int | None = None,
                tip_tilt_apart: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Modal-to-command matrix and prior variances of the DM-space K-L modes.

    Parameters
    ----------
    influence : InfluenceFunctions
        The mirror (its pupil is where the modes are orthonormal).
    r0 : float
        Fried parameter [m] at the phase's wavelength, ``> 0``.
    outer_scale : float
        Von Karman outer scale ``L0`` [m], ``> 0`` (``inf``: Kolmogorov).
    n_modes : int, optional
        Modes kept, ``1 <= n_modes <= n_valid - 1`` (default all: ``n_valid - 1``).
    tip_tilt_apart : bool
        True (default): modes 1-2 are the DM's best tip and tilt, the rest diagonalise
        the prior in their complement (OOPAO, COMPASS); False: every mode diagonalises
        the prior (piston removed only).

    Returns
    -------
    m2c : (n_valid, n_modes) float64
        Actuator strokes of each mode (unit-RMS surface over the pupil).
    variances : (n_modes,) float64
        Prior variance [rad^2] of each mode's coefficient.

    Notes
    -----
    Builds are cached by their inputs (``modalinfo/bases/_dm_kl_cache.py``): the last
    few in the process, and on disk in the directory the environment variable
    ``MODALINFO_DM_KL_CACHE`` names, if set (one checksummed ``.npz`` per build). A cached
    build returns the same arrays bit for bit (copies).
    """
    if not isinstance(influence, InfluenceFunctions):
        raise TypeError("`influence` must be a modalinfo.bases.InfluenceFunctions; got "
                        f"{type(influence).__name__}.")
    r0 = check_real(r0, "r0", minimum=0.0, strict_min=True)
    ratio = influence.pupil.diameter / r0
    if not _D_OVER_R0[0] <= ratio <= _D_OVER_R0[1]:
        # the prior scales as (D / r0)^(5/3): beyond these bounds it overflowed (scipy's
        # "array must not contain infs or NaNs" at r0 = 1e-300) or underflowed to 0, whose
        # "modes" were arbitrary (r0 = 1e300 m gave variances 0 and no error; audit 9)
        raise ValueError(
            f"`r0` must give D / r0 in [{_D_OVER_R0[0]:g}, {_D_OVER_R0[1]:g}] (D = "
            f"{influence.pupil.diameter:g} m, the pupil's diameter; the prior scales as "
            f"(D / r0)^(5/3) and overflows or underflows beyond); got r0={r0:g} m.")
    outer_scale = check_real(outer_scale, "outer_scale", minimum=0.0, strict_min=True,
                             allow_inf=True)
    if not isinstance(tip_tilt_apart, bool | np.bool_):
        raise TypeError(f"`tip_tilt_apart` must be a bool; got {tip_tilt_apart!r}.")
    n_act = influence.n_valid
    if n_act < 4:
        raise ValueError(f"`influence` must have at least 4 valid actuators; got {n_act}.")
    n_keep = n_act - 1 if n_modes is None else check_int(n_modes, "n_modes", minimum=1,
                                                         maximum=n_act - 1)
    key = _dm_kl_cache.build_key(influence, r0, outer_scale, n_keep, bool(tip_tilt_apart))
    return _dm_kl_cache.cached_build(key, lambda: _build(influence, r0, outer_scale, n_keep,
                                                         bool(tip_tilt_apart)))


def _build(influence: InfluenceFunctions, r0: float, outer_scale: float, n_keep: int,
           tip_tilt_apart: bool) -> tuple[np.ndarray, np.ndarray]:
    """Build the K-L modes of :func:`dm_kl_modes` (arguments checked there)."""
    n_act = influence.n_valid
    s_mat = _command_prior(influence, r0, outer_scale)
    gram = influence.gram()
    pupil = influence.pupil
    mask = np.asarray(pupil.mask)
    n_fixed = 3 if tip_tilt_apart else 1
    targets = np.stack([np.ones(pupil.n_valid), np.asarray(pupil.x)[mask],
                        np.asarray(pupil.y)[mask]], axis=1)[:, :n_fixed]
    # the DM's least-squares fits of piston, x, y, orthonormalised in that order in the
    # DM metric (Gram-Schmidt, twice for rounding): tip and tilt are the DM's best ones
    chol = linalg.cholesky(gram, lower=True)
    fits = linalg.cho_solve((chol, True), influence.matrix.T @ targets / pupil.n_valid)
    fixed = np.empty((n_act, n_fixed))
    for k in range(n_fixed):
        vec = fits[:, k].copy()
        for _ in range(2):
            vec -= fixed[:, :k] @ (fixed[:, :k].T @ (gram @ vec))
        fixed[:, k] = vec / math.sqrt(vec @ gram @ vec)
    # whitened coordinates z = L^T c (G = L L^T): mirror shapes orthonormal, the prior
    # L^-1 S L^-T; the complement of the fixed directions is spanned by the last
    # columns of the Householder Q of L^T F, applied as its 1-3 reflectors (O(n^2)
    # each) rather than as an n x n matrix, so modes >= 3 are orthogonal to them to
    # rounding whatever their variance
    # L^-1 S L^-T by LAPACK's sygst (its lower triangle; half the work of two triangular
    # solves with n right-hand sides, 0.16 against 0.32 s of CPU at 1,584)
    std, info = linalg.lapack.dsygst(s_mat, chol, itype=1, lower=1)
    if info != 0:  # pragma: no cover - only for an illegal argument
        raise RuntimeError(f"LAPACK dsygst failed (info={info})")
    std = np.tril(std) + np.tril(std, -1).T
    (qr_raw, tau), _ = linalg.qr(chol.T @ fixed, mode="raw")
    reflectors = []
    for k in range(n_fixed):
        vec = np.zeros(n_act)
        vec[k] = 1.0
        vec[k + 1:] = qr_raw[k + 1:, k]
        reflectors.append((vec, tau[k]))
    for vec, t in reflectors:  # std <- H std H, H = I - t v v^T (Q^T std Q, Q = H1 H2 H3)
        av = std @ vec
        std -= t * np.outer(vec, av) + t * np.outer(av, vec) - t * t * (vec @ av) * np.outer(
            vec, vec)
    prior = std[n_fixed:, n_fixed:]
    prior = 0.5 * (prior + prior.T)
    dim = n_act - n_fixed
    n_eig = max(1, min(dim, n_keep - (n_fixed - 1)))  # eigenvectors after tip/tilt
    # MRRR for the largest n_eig only when they are fewer than a third of the dimension
    # (a 76 x 76 altitude DM: 4,600 actuators, ~1,500 modes), else divide and conquer for
    # all of them: at 1,581 MRRR took 0.48 / 0.79 / 2.4 s of CPU for 100 / 500 / 1,498
    # eigenpairs, divide and conquer 0.85-0.90 s for all (benchmarks/RESULTS.md, "4-m loop")
    if n_eig < dim / _MRRR_SHARE:
        values, vectors = linalg.eigh(prior, subset_by_index=[dim - n_eig, dim - 1],
                                      driver="evr")
    else:  # ascending: the largest n_eig are the last columns
        values, vectors = np.linalg.eigh(prior)
        values, vectors = values[dim - n_eig:], vectors[:, dim - n_eig:]
    z = np.zeros((n_act, vectors.shape[1]))
    z[n_fixed:] = vectors
    for vec, t in reversed(reflectors):  # z <- Q z = H1 H2 H3 z
        z -= t * np.outer(vec, vec @ z)
    vectors = linalg.solve_triangular(chol.T, z, lower=False)
    order = np.argsort(values)[::-1]
    values, vectors = values[order], vectors[:, order]
    if tip_tilt_apart:
        m2c = np.concatenate([fixed[:, 1:3], vectors], axis=1)[:, :n_keep]
        tt = np.einsum("ik,ij,jk->k", fixed[:, 1:3], s_mat, fixed[:, 1:3])
        var = np.concatenate([tt, values])[:n_keep]
    else:
        m2c = vectors[:, :n_keep]
        var = values[:n_keep]
    m2c = np.array(m2c)
    # deterministic signs: the largest-magnitude stroke of every K-L mode positive
    if tip_tilt_apart:
        fix = slice(2, None)
    else:
        fix = slice(0, None)
    sub = m2c[:, fix]
    idx = np.argmax(np.abs(sub), axis=0)
    signs = np.sign(sub[idx, np.arange(sub.shape[1])])
    signs[signs == 0] = 1.0
    m2c[:, fix] = sub * signs
    return np.ascontiguousarray(m2c), np.clip(var, 0.0, None)


class DMKLBasis(ModalBasis):
    """DM-space K-L modes: surfaces of a mirror's K-L commands on its pupil.

    Build with :meth:`from_influence`. A :class:`~modalinfo.bases.ModalBasis` like the
    others (reorder, project, log, export); the pixel matrix is
    ``influence.matrix @ m2c`` (dense ``(n_pupil_pixels, M)``).

    Parameters
    ----------
    influence : InfluenceFunctions
    m2c : (n_valid, M) array_like
        Actuator strokes of each mode.
    variances : (M,) array_like
        Prior variance of each mode [rad^2].
    labels : sequence of str, optional
        Default ``"DMKL1"``...

    Attributes
    ----------
    m2c : (n_valid, M) float64
        Modal-to-command matrix.
    variances : (M,) float64
        Prior variances [rad^2] (at the ``r0`` of :meth:`from_influence`).
    influence : InfluenceFunctions
    """

    def __init__(self, influence: InfluenceFunctions, m2c, variances, labels=None) -> None:
        if not isinstance(influence, InfluenceFunctions):
            raise TypeError("`influence` must be a modalinfo.bases.InfluenceFunctions; got "
                            f"{type(influence).__name__}.")
        m2c = as_float_array(m2c, "m2c", ndim=2, copy=True)
        if m2c.shape[0] != influence.n_valid:
            raise ValueError(f"`m2c` must have n_valid={influence.n_valid} rows (one per "
                             f"actuator); got shape {m2c.shape}.")
        var = as_float_array(variances, "variances", shape=(m2c.shape[1],), copy=True)
        if labels is None:
            labels = [f"DMKL{k + 1}" for k in range(m2c.shape[1])]
        matrix = np.asarray(influence.matrix @ m2c)
        super().__init__(matrix, influence.pupil, labels, _copy=False)
        m2c.flags.writeable = False
        var.flags.writeable = False
        self._influence = influence
        self._m2c = m2c
        self._variances = var

    @classmethod
    def from_influence(cls, influence: InfluenceFunctions, r0: float,
                       outer_scale: float = np.inf, *, n_modes: int | None = None,
                       tip_tilt_apart: bool = True) -> DMKLBasis:
        """DM-space K-L modes of von Karman turbulence (see :func:`dm_kl_modes`)."""
        m2c, var = dm_kl_modes(influence, r0, outer_scale, n_modes=n_modes,
                               tip_tilt_apart=tip_tilt_apart)
        return cls(influence, m2c, var)

    @property
    def m2c(self) -> np.ndarray:
        """Modal-to-command matrix ``(n_valid, M)``."""
        return self._m2c

    @property
    def variances(self) -> np.ndarray:
        """Prior variance of each mode ``(M,)`` [rad^2]."""
        return self._variances

    @property
    def influence(self) -> InfluenceFunctions:
        """The mirror's influence functions."""
        return self._influence

    def _permute_extra(self, new: ModalBasis, index: np.ndarray) -> None:
        m2c = np.ascontiguousarray(self._m2c[:, index])
        var = self._variances[index].copy()
        m2c.flags.writeable = False
        var.flags.writeable = False
        new._m2c = m2c
        new._variances = var
