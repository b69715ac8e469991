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

With ``--fe-baseline FILE`` (an earlier ``modalinfo/ordering/fitting_error.py``, e.g.
``git show REV:modalinfo/ordering/fitting_error.py > /tmp/fe_before.py``) the fitting-error
"before" is that module's ``fitting_error`` (same run, CPU time, medians), checked equal bit
for bit where both keep every frame; ``--skip-kl`` leaves the K-L tables out. The
3,000 x ``--frames`` row also times the bands from every frame (``band_frames=T``) and
reports how far the default 20,000-frame bands are from them.

Run: PYTHONPATH=. python benchmarks/bench_centre_scale.py [--frames 100000] [--repeats 3]
     [--fe-baseline /tmp/fe_before.py] [--skip-kl]
"""

import argparse
import functools
import importlib.util
import os
import sys

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
from _common import timed  # noqa: E402

from modalinfo.bases import KLBasis, Pupil  # noqa: E402
from modalinfo.bases import turbulence as tb  # noqa: E402
from modalinfo.bases.kl import _eig_blocks, _eig_by_symmetry, _fix_signs, default_zernike_modes  # noqa: E402
from modalinfo.ordering import fitting_error  # noqa: E402

median_time = timed  # wall time
cpu_time = functools.partial(timed, cpu=True)


def load_module(path, name):
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


def kl_before(n_modes):
    modes = default_zernike_modes(n_modes)
    cov = tb._dense_zernike_covariance(modes, np.inf, 1.0)
    values, vectors = _eig_by_symmetry(cov, modes)
    return values[:n_modes], np.ascontiguousarray(_fix_signs(vectors[:, :n_modes]))


def kl_after(n_modes):
    modes = default_zernike_modes(n_modes)
    return _eig_blocks(tb._covariance_blocks(modes, np.inf, 1.0), modes, n_modes)


def fitting_section(args):
    old = None if args.fe_baseline is None else load_module(args.fe_baseline, "fe_baseline")
    print("## fitting-error curve, Parseval (orthonormal basis, 3,300 pixels), CPU time [s]")
    print("| modes x frames | before | after | ratio | per_frame kept | band frames | "
          "equal bits (mean, total, bands) |")
    print("|---|---|---|---|---|---|---|")
    rng = np.random.default_rng(30)
    n_pix = 3300
    for n_modes, n_frames in ((27, 7000), (3000, args.small_frames)):
        q, _ = np.linalg.qr(rng.standard_normal((n_pix, n_modes)))
        basis = q * np.sqrt(n_pix)
        del q
        sigma = np.arange(1, n_modes + 1) ** (-11 / 12)
        a = rng.standard_normal((n_frames, n_modes))
        a *= sigma
        reps = args.repeats if n_modes < 1000 else 1
        t_new, new = cpu_time(lambda a=a, b=basis: fitting_error(a, b, method="parseval"), reps)
        if old is not None:
            t_old, ref = cpu_time(
                lambda a=a, b=basis: old.fitting_error(a, b, method="parseval"), reps)
            same = (np.array_equal(ref.mean, new.mean) and np.array_equal(ref.total, new.total)
                    and np.array_equal(ref.bands, new.bands))
            if new.per_frame is not None:
                same = same and np.array_equal(ref.per_frame, new.per_frame)
            del ref
            before, ratio = f"{t_old:.3f}", f"{t_old / t_new:.1f}"
        else:
            before = ratio = same = "-"
        print(f"| {n_modes} x {n_frames} | {before} | {t_new:.3f} | {ratio} | "
              f"{new.per_frame is not None} | {new.band_frames or n_frames} | {same} |",
              flush=True)
        del new, a

    n_modes, n_frames = 3000, args.frames
    q, _ = np.linalg.qr(rng.standard_normal((n_pix, n_modes)))
    basis = q * np.sqrt(n_pix)
    del q
    var = np.arange(1, n_modes + 1) ** (-11 / 6)
    a = rng.standard_normal((n_frames, n_modes))
    a *= np.sqrt(var)
    t_new, new = cpu_time(lambda: fitting_error(a, basis, method="parseval"), 1, warm=False)
    expected = np.concatenate([np.cumsum(var[::-1])[::-1][1:], [0.0]])
    dev = np.max(np.abs(new.mean[:-1] / expected[:-1] - 1))
    print(f"\n{n_modes} x {n_frames} ({a.nbytes / 1e9:.1f} GB of coefficients), default "
          f"(per_frame kept: {new.per_frame is not None}, bands from {new.band_frames} "
          f"frames): {t_new:.2f} s CPU; max |mean curve / sum_(k>n) sigma_k^2 - 1| = "
          f"{dev:.2%}", flush=True)
    t_all, full = cpu_time(
        lambda: fitting_error(a, basis, method="parseval", band_frames=n_frames), 1, warm=False)
    same = np.array_equal(full.mean, new.mean) and np.array_equal(full.total, new.total)
    rel = np.abs(new.bands[:, :-1] / full.bands[:, :-1] - 1).max(axis=1)
    print(f"bands from every frame (band_frames=T): {t_all:.2f} s CPU; mean and totals equal "
          f"bits: {same}; 20,000-frame bands vs every-frame bands, max relative difference "
          f"per level {dict(zip(new.percentiles, np.round(rel, 5), strict=True))}", flush=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--frames", type=int, default=100_000)
    parser.add_argument("--small-frames", type=int, default=20_000,
                        help="frames of the before/after comparison at 3,000 modes")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--fe-baseline", default=None)
    parser.add_argument("--skip-kl", action="store_true")
    args = parser.parse_args()
    if not args.skip_kl:
        kl_section(args)
    fitting_section(args)


def kl_section(args):
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


if __name__ == "__main__":
    main()
