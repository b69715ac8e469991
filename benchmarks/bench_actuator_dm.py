"""Benchmark: the actuator DM's per-frame surface and its DM-space K-L build (issue 29).

CPU times of this process (``time.process_time``; medians over repeats after a warm-up,
so numba compilation is excluded), in the same run, of

  - the mirror surface for one command vector, 44 x 44 actuators (DKIST's 1,600-actuator
    DM; coupling 0.35) on a 172-pixel 4-m pupil:
      * ``InfluenceFunctions.surface`` (separable banded kernel, what the loop applies),
      * ``InfluenceFunctions.matrix @ c`` (the sparse CSR operator),
      * hcipy's ``DeformableMirror.surface`` over ``make_gaussian_influence_functions``
        with the same grid, pitch and crosstalk (all 44 x 44 actuators, hcipy's sparse
        influence matrix);
  - the same on the meta-pupil of a 60" field at 10 km (EST-like altitude DM): a
    6.91-m disc, 298 pixels across, 76 x 76 actuators at the same pitch;
  - the closed-loop mirror's forward (``m2c @ k`` for 1,519 K-L coefficients, then the
    surface);
  - the DM-space K-L build (``dm_kl_modes``: FFT projection of the von Karman prior,
    Cholesky whitening, eigen-decomposition) at 44 x 44 on 172 pixels, all modes
    (``--meta-kl``: also 1,500 modes of the 76 x 76 altitude DM).

BLAS runs on one thread (threadpoolctl), as the project's golden runs, because a
shared 2-core machine under load makes a multithreaded ``eigh`` 20x slower.

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_actuator_dm.py [--repeats 20]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from _common import cpu_median

from modalinfo.bases import InfluenceFunctions, MaskedPupil, Pupil, dm_kl_modes
from modalinfo.bases.dm_kl import _command_prior

ARCSEC = math.pi / 180 / 3600


def surface_rows(label: str, pupil, n_act: int, pitch: float, repeats: int) -> list:
    import hcipy

    f = InfluenceFunctions(pupil, n_act, pitch)
    c = np.random.default_rng(0).standard_normal(f.n_valid)
    mat = f.matrix
    sep = cpu_median(lambda: f.surface(c), repeats)
    csr = cpu_median(lambda: mat @ c, repeats)
    grid = hcipy.make_uniform_grid([pupil.n_pixels, pupil.n_pixels],
                                   [pupil.diameter, pupil.diameter])
    ifs = hcipy.make_gaussian_influence_functions(grid, n_act, pitch, crosstalk=f.coupling)
    dm = hcipy.DeformableMirror(ifs)
    acts = np.random.default_rng(0).standard_normal((2, n_act * n_act))
    calls = [0]

    def hcipy_surface():
        # a new command every call: hcipy caches the surface of unchanged actuators
        calls[0] += 1
        dm.actuators = acts[calls[0] % 2]
        return dm.surface

    hc = cpu_median(hcipy_surface, repeats)
    what = (f"{label}: {pupil.n_valid} px, {f.n_valid} valid of {n_act}x{n_act}, "
            f"{mat.nnz} non-zeros")
    return [(what, "modalinfo surface (separable)", sep, 1.0),
            ("", "modalinfo matrix @ c (CSR)", csr, csr / sep),
            ("", "hcipy DeformableMirror.surface", hc, hc / sep)]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=20)
    parser.add_argument("--meta-kl", action="store_true",
                        help="also build 1,500 K-L modes of the 76 x 76 altitude DM (~1 min)")
    args = parser.parse_args()
    from threadpoolctl import threadpool_limits

    rows = []
    with threadpool_limits(limits=1, user_api="blas"):
        diameter, n_pix, n_act = 4.0, 172, 44
        pitch = diameter / (n_act - 1)
        pupil = Pupil(n_pix, diameter)
        rows += surface_rows("pupil", pupil, n_act, pitch, args.repeats)
        dx = diameter / n_pix
        disc = diameter + 2 * 10e3 * math.tan(30 * ARCSEC)
        n_meta = 2 * math.ceil(disc / 2 / dx)
        centres = (np.arange(n_meta) + 0.5 - n_meta / 2) * dx
        yy, xx = np.meshgrid(centres, centres, indexing="ij")
        meta = MaskedPupil(np.hypot(xx, yy) <= disc / 2, diameter=n_meta * dx)
        n_meta_act = math.ceil(disc / pitch) + 1
        rows += surface_rows(f'60" at 10 km ({disc:.2f} m)', meta, n_meta_act, pitch,
                             args.repeats)
        if args.meta_kl:
            fm = InfluenceFunctions(meta, n_meta_act, pitch)
            t0 = time.process_time()
            dm_kl_modes(fm, 0.07, 27.0, n_modes=1500)
            rows.append((f"K-L build, {fm.n_valid} actuators, {meta.n_pixels} px",
                         "dm_kl_modes, 1,500 modes", time.process_time() - t0, 1.0))

        f = InfluenceFunctions(pupil, n_act, pitch)
        f.gram()  # the metric (0.3 s) is the mirror's, built once with it
        t0 = time.process_time()
        _command_prior(f, 0.07, 27.0)
        prior = time.process_time() - t0
        t0 = time.process_time()
        m2c, var = dm_kl_modes(f, 0.07, 27.0)
        build = time.process_time() - t0
        k = np.random.default_rng(1).standard_normal(m2c.shape[1])
        fwd = cpu_median(lambda: f.surface(m2c @ k), args.repeats)
        strokes = cpu_median(lambda: m2c @ k, args.repeats)
        rows.append((f"loop forward, {m2c.shape[1]} K-L modes", "m2c @ k then surface", fwd,
                     1.0))
        rows.append(("", "of which m2c @ k (dense)", strokes, strokes / fwd))
        rows.append((f"K-L build, {f.n_valid} actuators, 172 px", "dm_kl_modes", build, 1.0))
        rows.append(("", "of which the prior (FFT projection)", prior, prior / build))

    print(f"{'case':64s} {'implementation':34s} {'time':>12s} {'ratio':>7s}")
    for case, impl, t, ratio in rows:
        unit = f"{t * 1e3:9.3f} ms" if t < 1 else f"{t:9.2f} s "
        print(f"{case:64s} {impl:34s} {unit:>12s} {ratio:7.2f}")


if __name__ == "__main__":
    main()
