"""Benchmark: the correlating Shack-Hartmann's cost per subaperture, and table1's frame rate.

Two costs per subaperture and frame, each the median of ``--repeats`` timed blocks
(after one warm-up block that includes numba's JIT), in process CPU time
(``time.process_time``: the other jobs on a shared machine do not inflate it):

- correlation: ``measure_shifts`` on a batch of subaperture images, SDF and ADF^2 by the
  numba kernel, the same SDF surfaces by plain numpy slicing (``shifts._surfaces_numpy``,
  one vectorised pass per lag) and CFI by numpy's real FFT; the ratio numpy / numba is
  printed;
- image formation: ``CorrelatingSubapertures.images`` (one MFT PSF and one FFT
  convolution per sub-direction, blending, photon and read noise) for 1 and 3x3
  sub-directions.

The frame rate of a table1-like correlating WFS pair is then estimated as
``1 / sum_wfs n_valid * (formation + correlation)``: the valid subapertures are counted
from the ``table1`` preset's geometric sensors (``closedloop.optics.wfs``), the field of each
subaperture image is its WFS's field of view (60" ground, 20" upper) at ``--pixel``
arcsec per pixel, the subaperture pitch is its meta-pupil over 16, and the pupil is
sampled at the loop's 6.25 cm. The goal of issue 20 is >= 100 frames/s.

Run: PYTHONPATH=. python benchmarks/bench_shifts.py [--repeats 5] [--pixel 0.5] [--max-shift 2]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from closedloop import presets
from closedloop.optics import shifts
from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.dm import DeformableMirror
from closedloop.optics.geometry import Geometry, wfs_meta_pupil
from closedloop.optics.granulation import granulation_scene
from closedloop.optics.wfs import WavefrontSensor


def cpu_median(fn, repeats):
    fn()  # warm-up (JIT, caches)
    times = []
    for _ in range(repeats):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return float(np.median(times))


def time_correlation(ref, imgs, max_shift, repeats):
    """CPU time per subaperture [s] of each correlation engine on one batch."""
    refs = np.ascontiguousarray(np.broadcast_to(ref, imgs.shape))
    lag = max_shift + 1
    win = imgs.shape[-1] - 2 * lag
    r0 = (imgs.shape[-1] - win) // 2
    per = {}
    for name, fn in [
        ("sdf numba", lambda: shifts.measure_shifts(ref, imgs, method="sdf",
                                                    max_shift=max_shift)),
        ("adf2 numba", lambda: shifts.measure_shifts(ref, imgs, method="adf2",
                                                     max_shift=max_shift)),
        ("sdf surfaces numba", lambda: shifts._surfaces_difference(
            refs, imgs, r0, r0, win, lag, True)),
        ("sdf surfaces numpy", lambda: shifts._surfaces_numpy(
            refs, imgs, r0, r0, win, lag, True)),
        ("cfi numpy fft", lambda: shifts.measure_shifts(ref, imgs, method="cfi",
                                                        max_shift=max_shift)),
    ]:
        per[name] = cpu_median(fn, repeats) / imgs.shape[0]
        print(f"  correlation {name:20s} {per[name] * 1e6:9.1f} us / subaperture")
    print(f"  numpy / numba (SDF surfaces): "
          f"{per['sdf surfaces numpy'] / per['sdf surfaces numba']:.1f}x")
    return per


def table1_wfs():
    """(n_valid, field [arcsec], pitch [m]) of table1's two WFSs."""
    cfg = presets.get("table1")
    g = Geometry(cfg)
    out = []
    for j, w in enumerate(cfg.wfss):
        dm = DeformableMirror(g, w.dm)
        s = WavefrontSensor(g, j, dm)
        out.append((s.n_valid_subapertures, w.field_of_view,
                    wfs_meta_pupil(cfg, j) / w.n_subapertures))
    return out, cfg.telescope.diameter / cfg.telescope.n_pixels


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--pixel", type=float, default=0.5, help="arcsec per WFS pixel")
    ap.add_argument("--max-shift", type=int, default=2)
    ap.add_argument("--batch", type=int, default=32, help="subapertures per timed call")
    args = ap.parse_args()
    wfss, dx = table1_wfs()
    rng = np.random.default_rng(0)
    print(f"pixel {args.pixel}\"  max_shift {args.max_shift}  batch {args.batch}  "
          f"repeats {args.repeats} (CPU time, median)")
    total = {}
    for n_valid, fov, pitch in wfss:
        n_img = int(round(fov / args.pixel))
        n_scene = 1 << max(7, math.ceil(math.log2(2 * n_img)))
        # granules must span 2 scene pixels: coarse pixels bin a finer scene
        binning = max(1, math.ceil(args.pixel / 0.5))
        scene = granulation_scene(n_scene * binning, args.pixel / binning, seed=1)
        scene = scene.reshape(n_scene, binning, n_scene, binning).mean(axis=(1, 3))
        p = max(2, int(round(pitch / dx)))
        print(f"\nWFS field {fov:g}\": {n_valid} valid subapertures of {pitch:.3f} m "
              f"({p} pupil px), images {n_img} x {n_img} px")
        cs = CorrelatingSubapertures(scene, args.pixel, pitch, p, n_img,
                                     max_shift=args.max_shift)
        imgs = cs.images(rng.normal(0, 0.5, (1, args.batch, p, p)), rng=rng)
        ref = imgs[0]
        per = time_correlation(ref, imgs, args.max_shift, args.repeats)
        for n_patches in (1, 3):
            cs_p = CorrelatingSubapertures(scene, args.pixel, pitch, p, n_img,
                                           n_patches=n_patches, max_shift=args.max_shift)
            phase = rng.normal(0, 0.5, (n_patches ** 2, args.batch, p, p))
            t = cpu_median(lambda cs_p=cs_p, phase=phase: cs_p.images(phase, rng=rng),
                           args.repeats) / args.batch
            per[f"form {n_patches}"] = t
            print(f"  image formation, {n_patches}x{n_patches} sub-directions "
                  f"(support {cs_p.support} px, pupil x{cs_p.pupil_oversampling}): "
                  f"{t * 1e6:9.1f} us / subaperture")
        total[fov] = (n_valid, per)
    print("\ntable1-like correlating WFS pair, frames/s (goal >= 100):")
    for method in ("sdf numba", "cfi numpy fft"):
        for n_patches in (1, 3):
            frame = sum(n * (per[f"form {n_patches}"] + per[method])
                        for n, per in total.values())
            corr = sum(n * per[method] for n, per in total.values())
            print(f"  {method:14s} {n_patches}x{n_patches} patches: {1 / frame:7.1f} frames/s "
                  f"(correlation alone {1 / corr:7.1f})")


if __name__ == "__main__":
    main()
