"""numba kernels of the modal bases (no validation, no randomness)."""

from __future__ import annotations

import numpy as np

from modalinfo._numba import jit


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
def zernike_matrix(rho, theta, n_modes, m_modes, out):
    """Fill out[p, k] = N_k R_{n_k}^{|m_k|}(rho_p) * {cos, sin, 1}(|m_k| theta_p).

    Unit-RMS (Noll) normalisation: N = sqrt(n + 1) for m = 0, sqrt(2 (n + 1)) otherwise;
    m > 0 cosine, m < 0 sine.

    rho, theta : (P,) float64 IN ; n_modes, m_modes : (M,) int64 IN ;
    out : (P, M) float64 OUT
    """
    n_max = 0
    for k in range(n_modes.shape[0]):
        if n_modes[k] > n_max:
            n_max = n_modes[k]
    n_pix = rho.shape[0]
    n_m = m_modes.shape[0]
    norm = np.empty(n_m)
    for k in range(n_m):
        if m_modes[k] == 0:
            norm[k] = np.sqrt(n_modes[k] + 1.0)
        else:
            norm[k] = np.sqrt(2.0 * (n_modes[k] + 1.0))
    # Kintner coefficients depend only on (n, m): tabulate once
    coef = np.zeros((n_max + 1, n_max + 1, 4))
    for m in range(n_max + 1):
        for nn in range(m + 4, n_max + 1, 2):
            k1, k2, k3, k4 = kintner_coefficients(nn, m)
            coef[nn, m, 0] = k2 / k1
            coef[nn, m, 1] = k3 / k1
            coef[nn, m, 2] = k4 / k1
    table = np.empty((n_max + 1, n_max + 1))  # table[n, m] = R_n^m
    cos_t = np.empty(n_max + 1)
    sin_t = np.empty(n_max + 1)
    for p in range(n_pix):
        r = rho[p]
        r2 = r * r
        c1 = np.cos(theta[p])
        s1 = np.sin(theta[p])
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
        for k in range(n_m):
            m = m_modes[k]
            if m > 0:
                out[p, k] = norm[k] * table[n_modes[k], m] * cos_t[m]
            elif m < 0:
                out[p, k] = norm[k] * table[n_modes[k], -m] * sin_t[-m]
            else:
                out[p, k] = norm[k] * table[n_modes[k], 0]
