"""numba kernels of the modal bases (no validation, no randomness)."""

from __future__ import annotations

import numpy as np

from modalinfo.common.jit import jit


@jit
def kintner_coefficients(n, m):
    """Coefficients of Kintner's recurrence for R_n^m from R_{n-2}^m and R_{n-4}^m.

    ``K1 R_n = (K2 rho^2 + K3) R_{n-2} + K4 R_{n-4}`` (Kintner 1976; Chong et al. 2003),
    valid for ``n >= m + 4``.
    """
    k1 = (n + m) * (n - m) * (n - 2) / 2.0
    k2 = 2.0 * n * (n - 1) * (n - 2)
    k3 = -1.0 * m * m * (n - 1) - n * (n - 1.0) * (n - 2)
    k4 = -n * (n + m - 2.0) * (n - m - 2) / 2.0
    return k1, k2, k3, k4


@jit
def radial(n, m, rho, out):
    """Zernike radial polynomial R_n^m(rho) for every rho (m >= 0, n - m even).

    rho : (P,) float64 IN ; out : (P,) float64 OUT
    """
    for p in range(rho.shape[0]):
        r = rho[p]
        r2 = r * r
        rm = r**m
        prev2 = rm  # R_m^m
        if n == m:
            out[p] = prev2
            continue
        prev1 = rm * ((m + 2.0) * r2 - (m + 1.0))  # R_{m+2}^m
        for nn in range(m + 4, n + 1, 2):
            k1, k2, k3, k4 = kintner_coefficients(nn, m)
            cur = ((k2 * r2 + k3) * prev1 + k4 * prev2) / k1
            prev2 = prev1
            prev1 = cur
        out[p] = prev1


@jit
def _setup(n_modes, m_modes):
    """Maximum order, Noll norms and the Kintner coefficient table of a mode set."""
    n_max = 0
    for k in range(n_modes.shape[0]):
        if n_modes[k] > n_max:
            n_max = n_modes[k]
    n_m = m_modes.shape[0]
    norm = np.empty(n_m)
    for k in range(n_m):
        if m_modes[k] == 0:
            norm[k] = np.sqrt(n_modes[k] + 1.0)
        else:
            norm[k] = np.sqrt(2.0 * (n_modes[k] + 1.0))
    # Kintner coefficients depend only on (n, m): tabulate once
    coef = np.zeros((n_max + 1, n_max + 1, 3))
    for m in range(n_max + 1):
        for nn in range(m + 4, n_max + 1, 2):
            k1, k2, k3, k4 = kintner_coefficients(nn, m)
            coef[nn, m, 0] = k2 / k1
            coef[nn, m, 1] = k3 / k1
            coef[nn, m, 2] = k4 / k1
    return n_max, norm, coef


@jit(inline="always")
def _pixel_tables(r, c1, s1, n_max, coef, table, cos_t, sin_t):
    """Fill table[n, m] = R_n^m(r) and cos_t[m], sin_t[m] = cos, sin(m theta), m <= n_max.

    ``c1, s1 = cos(theta), sin(theta)``. The angle recurrence uses only products, sums
    and differences, which IEEE arithmetic rounds sign-symmetrically: pixels whose
    ``(c1, s1)`` are exact mirrors (``(-c1, s1)``, ``(c1, -s1)``, ``(s1, c1)``) get exact
    mirror values of every ``cos(m theta)``, ``sin(m theta)``.
    """
    r2 = r * r
    cos_t[0] = 1.0
    sin_t[0] = 0.0
    rm = 1.0
    for m in range(n_max + 1):
        if m > 0:
            cos_t[m] = cos_t[m - 1] * c1 - sin_t[m - 1] * s1
            sin_t[m] = sin_t[m - 1] * c1 + cos_t[m - 1] * s1
            rm *= r
        table[m, m] = rm
        if m + 2 <= n_max:
            table[m + 2, m] = rm * ((m + 2.0) * r2 - (m + 1.0))
        for nn in range(m + 4, n_max + 1, 2):
            table[nn, m] = (coef[nn, m, 0] * r2 + coef[nn, m, 1]) * table[nn - 2, m] + coef[
                nn, m, 2
            ] * table[nn - 4, m]


@jit
def zernike_matrix(rho, theta, n_modes, m_modes, out):
    """Fill out[p, k] = N_k R_{n_k}^{|m_k|}(rho_p) * {cos, sin, 1}(|m_k| theta_p).

    Unit-RMS (Noll) normalisation: N = sqrt(n + 1) for m = 0, sqrt(2 (n + 1)) otherwise;
    m > 0 cosine, m < 0 sine.

    rho, theta : (P,) float64 IN ; n_modes, m_modes : (M,) int64 IN ;
    out : (P, M) float64 OUT
    """
    n_max, norm, coef = _setup(n_modes, m_modes)
    table = np.empty((n_max + 1, n_max + 1))
    cos_t = np.empty(n_max + 1)
    sin_t = np.empty(n_max + 1)
    for p in range(rho.shape[0]):
        _pixel_tables(rho[p], np.cos(theta[p]), np.sin(theta[p]), n_max, coef, table, cos_t,
                      sin_t)
        for k in range(m_modes.shape[0]):
            mm = m_modes[k]
            if mm > 0:
                out[p, k] = norm[k] * table[n_modes[k], mm] * cos_t[mm]
            elif mm < 0:
                out[p, k] = norm[k] * table[n_modes[k], -mm] * sin_t[-mm]
            else:
                out[p, k] = norm[k] * table[n_modes[k], 0]


@jit
def zernike_combination_matrix(rho, cos_theta, sin_theta, n_modes, m_modes, indptr, indices,
                               weights, out):
    """Fill out[p, k] = sum_i weights * Z_i(rho_p, theta_p) over a sparse change of basis.

    Column k of the (n_z, K) change-of-basis matrix is given in compressed-column form:
    rows indices[indptr[k]:indptr[k+1]] with values weights[indptr[k]:indptr[k+1]]
    (row i is the Zernike (n_modes[i], m_modes[i])). Avoids building the (P, n_z) Zernike
    matrix: cost per pixel is the radial table plus the non-zeros.

    rho, cos_theta, sin_theta : (P,) float64 IN (cos and sin of the pixels' angles: exact
    mirrors at mirror pixels give exact mirror values, ``_pixel_tables``) ;
    n_modes, m_modes : (n_z,) int64 IN ; indptr : (K + 1,) int64 IN ;
    indices : (nnz,) int64 IN ; weights : (nnz,) float64 IN ; out : (P, K) float64 OUT
    """
    n_max, norm, coef = _setup(n_modes, m_modes)
    size = n_max + 1
    table = np.empty((size, size))
    ang = np.empty(2 * size)  # cos(m theta) at m, sin(m theta) at size + m
    nnz = indices.shape[0]
    # per non-zero: weight * norm, flat index of R_n^|m| in table, index in ang
    wn = np.empty(nnz)
    t_idx = np.empty(nnz, dtype=np.int64)
    a_idx = np.empty(nnz, dtype=np.int64)
    for q in range(nnz):
        i = indices[q]
        mm = m_modes[i]
        wn[q] = weights[q] * norm[i]
        t_idx[q] = n_modes[i] * size + abs(mm)
        a_idx[q] = mm if mm >= 0 else size - mm
    flat = table.reshape(size * size)
    n_cols = indptr.shape[0] - 1
    for p in range(rho.shape[0]):
        _pixel_tables(rho[p], cos_theta[p], sin_theta[p], n_max, coef, table, ang[:size],
                      ang[size:])
        for k in range(n_cols):
            acc = 0.0
            for q in range(indptr[k], indptr[k + 1]):
                acc += wn[q] * flat[t_idx[q]] * ang[a_idx[q]]
            out[p, k] = acc
