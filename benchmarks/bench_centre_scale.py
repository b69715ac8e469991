"""Benchmark: the centre at scale -- theoretical K-L and fitting-error curves (issue 30, item 2).

Times, before and after in the same run (medians over ``--repeats``, one warm-up call at
the small sizes; the 3,000-mode "before" runs once, it takes most of a minute):

- theoretical Kolmogorov K-L of M = 27, 500, 1000, 3000 modes over the default Zernike
  set (``3 M`` Zernikes, complete radial orders): "before" is the former all-pairs
  covariance (``turbulence._dense_zernike_covariance``) + ``kl._eig_by_symmetry`` +
  ``kl._fix_signs``; "after" is ``turbulence._covariance_blocks`` + ``kl._eig_blocks``,
  the path of ``KLBasis.from_turbulence``; the results are checked equal bit for bit;
  plus ``KLBasis.from_turbulence(Pupil(128), 3000)`` end to end (pixel matrix included);
- fitting-error curve of an orthonormal basis (QR of a Gaussian matrix on 3,300 pixels)
  by Parseval: "before" replays the former flow of ``fitting_error`` (reordered copy,
  whole-array ``_parseval``, ``np.percentile`` along the frame axis), "after" is
  ``fitting_error`` itself; checked equal bit for bit, and the frame-mean curve checked
  against its expectation ``sum_{k > n} sigma_k^2`` (the coefficients are drawn with
  known variances ``sigma_k^2 = k^(-11/6)``; at 10^5 frames its sampling error is ~0.5 %).

Run: PYTHONPATH=. python benchmarks/bench_centre_scale.py [--frames 100000] [--repeats 3]
"""

import argparse
import importlib
import time

import numpy as np

from modalinfo.bases import KLBasis, Pupil
from modalinfo.bases import turbulence as tb
from modalinfo.bases.kl import _eig_blocks, _eig_by_symmetry, _fix_signs, default_zernike_modes
from modalinfo.ordering import fitting_error

fe_module = importlib.import_module("modalinfo.ordering.fitting_error")


def median_time(func, repeats, warm=True):
    if warm:
        func()
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = func()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def kl_before(n_modes):
    modes = default_zernike_modes(n_modes)
    cov = tb._dense_zernike_covariance(modes, np.inf, 1.0)
    values, vectors = _eig_by_symmetry(cov, modes)
    return values[:n_modes], np.ascontiguousarray(_fix_signs(vectors[:, :n_modes]))


def kl_after(n_modes):
    modes = default_zernike_modes(n_modes)
    return _eig_blocks(tb._covariance_blocks(modes, np.inf, 1.0), modes, n_modes)


def fitting_before(a, basis, levels=(5.0, 25.0, 50.0, 75.0, 95.0)):
    """The former flow of fitting_error(method='parseval'), standard order."""
    idx = np.arange(a.shape[1])
    a = np.ascontiguousarray(a[:, idx])
    gram = (basis.T @ basis / basis.shape[0])[np.ix_(idx, idx)]
    assert np.max(np.abs(gram - np.eye(gram.shape[0]))) <= 1e-8
    per_frame, total = fe_module._parseval(a)
    return per_frame.mean(axis=0), np.percentile(per_frame, levels, axis=0), total


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--small-frames", type=int, default=20_000,
                        help="frames of the before/after comparison at 3,000 modes")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()

    print("## theoretical K-L (Kolmogorov), covariance + eigen-decomposition")
    print("| K-L modes | Zernikes | before [s] | after [s] | ratio | equal bits |")
    print("|---|---|---|---|---|---|")
    for n_modes in (27, 500, 1000, 3000):
        big = n_modes >= 3000
        reps = 1 if big else args.repeats
        t_old, old = median_time(lambda m=n_modes: kl_before(m), reps, warm=not big)
        t_new, new = median_time(lambda m=n_modes: kl_after(m), args.repeats, warm=True)
        same = np.array_equal(old[0], new[0]) and np.array_equal(old[1], new[1])
        print(f"| {n_modes} | {default_zernike_modes(n_modes).size} | {t_old:.3f} | "
              f"{t_new:.3f} | {t_old / t_new:.1f} | {same} |", flush=True)
    pupil = Pupil(128, diameter=4.0)
    t_full, _ = median_time(lambda: KLBasis.from_turbulence(pupil, 3000), 1, warm=False)
    print(f"\nKLBasis.from_turbulence(Pupil(128) ({pupil.n_valid} px), 3000): {t_full:.2f} s "
          "(first call, pixel matrix included)\n", flush=True)

    print("## fitting-error curve, Parseval (orthonormal basis, 3,300 pixels)")
    print("| modes x frames | before [s] | after [s] | ratio | equal bits |")
    print("|---|---|---|---|---|")
    rng = np.random.default_rng(30)
    n_pix = 3300
    for n_modes, n_frames in ((27, 7000), (3000, args.small_frames)):
        q, _ = np.linalg.qr(rng.standard_normal((n_pix, n_modes)))
        basis = q * np.sqrt(n_pix)
        sigma = np.arange(1, n_modes + 1) ** (-11 / 12)
        a = rng.standard_normal((n_frames, n_modes)) * sigma
        t_old, old = median_time(lambda a=a, b=basis: fitting_before(a, b), args.repeats)
        t_new, new = median_time(lambda a=a, b=basis: fitting_error(a, b, method="parseval"),
                                 args.repeats)
        same = (np.array_equal(old[0], new.mean) and np.array_equal(old[1], new.bands)
                and np.array_equal(old[2], new.total))
        print(f"| {n_modes} x {n_frames} | {t_old:.3f} | {t_new:.3f} | {t_old / t_new:.1f} | "
              f"{same} |", flush=True)
        del old, new

    n_modes, n_frames = 3000, args.frames
    q, _ = np.linalg.qr(rng.standard_normal((n_pix, n_modes)))
    basis = q * np.sqrt(n_pix)
    var = np.arange(1, n_modes + 1) ** (-11 / 6)
    a = rng.standard_normal((n_frames, n_modes)) * np.sqrt(var)
    t_new, new = median_time(lambda: fitting_error(a, basis, method="parseval"), 1,
                             warm=False)
    expected = np.concatenate([np.cumsum(var[::-1])[::-1][1:], [0.0]])
    dev = np.max(np.abs(new.mean[:-1] / expected[:-1] - 1))
    print(f"\n{n_modes} x {n_frames} ({a.nbytes / 1e9:.1f} GB of coefficients), after only: "
          f"{t_new:.2f} s; max |mean curve / expectation - 1| = {dev:.2%}")


if __name__ == "__main__":
    main()
