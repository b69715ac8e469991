"""Benchmark: building modal bases on a 256-pixel pupil.

Times (medians over repeats, one warm-up call each so numba compilation and import
costs are excluded) of
  - 100 Noll Zernike modes: modalinfo ZernikeBasis vs aotools.zernikeArray vs
    hcipy.make_zernike_basis (use_cache=False, else repeats are served from its cache);
  - 100 theoretical Kolmogorov K-L modes: modalinfo KLBasis.from_turbulence (Zernike
    covariance + eigen-decomposition over 324 Zernikes) vs aotools make_kl (Yorick-style
    generalised K-L on a polar grid; it needs an obscuration ri > 0, so ri = 0.01).
hcipy 0.7 has no K-L basis (its karhunen_loeve module is empty).

Run: /work/venv/bin/python benchmarks/bench_bases.py [--repeats 5]
"""

import argparse
import contextlib
import io
import warnings

from _common import median_time

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--n-pixels", type=int, default=256)
    parser.add_argument("--n-modes", type=int, default=100)
    args = parser.parse_args()
    n, m, r = args.n_pixels, args.n_modes, args.repeats

    import aotools
    import hcipy
    from aotools.functions.karhunenLoeve import make_kl

    grid = hcipy.make_pupil_grid(n, 1.0)
    rows = []
    ours = median_time(lambda: ZernikeBasis(Pupil(n), m), r)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ao = median_time(lambda: aotools.zernikeArray(m, n), r)
        hc = median_time(lambda: hcipy.make_zernike_basis(m, 1.0, grid, 1, use_cache=False), r)
    rows.append((f"{m} Zernike modes, {n} px", "modalinfo ZernikeBasis", ours, 1.0))
    rows.append(("", "aotools.zernikeArray", ao, ao / ours))
    rows.append(("", "hcipy.make_zernike_basis", hc, hc / ours))

    kl_ours = median_time(lambda: KLBasis.from_turbulence(Pupil(n), m), r)

    def aotools_kl():
        with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            make_kl(m, n, ri=0.01, nr=50, stf="kolmogorov")

    kl_ao = median_time(aotools_kl, max(1, r // 2))
    rows.append((f"{m} Kolmogorov K-L modes, {n} px", "modalinfo KLBasis.from_turbulence",
                 kl_ours, 1.0))
    rows.append(("", "aotools make_kl (ri=0.01, nr=50)", kl_ao, kl_ao / kl_ours))

    print(f"{'task':34s} {'code':36s} {'median [s]':>11s} {'ratio to ours':>14s}")
    for task, code, t, ratio in rows:
        print(f"{task:34s} {code:36s} {t:11.4f} {ratio:14.1f}")


if __name__ == "__main__":
    main()
