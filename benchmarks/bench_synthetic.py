"""Benchmark: making an open-loop Zernike telemetry log (8000 frames x 27 modes, 2 layers).

Times (medians over repeats, one warm-up call) of
  - modalinfo.telemetry.synthetic.open_loop_log: spectral (FFT-filtered) synthesis of the
    coefficients directly, with the Noll/von Karman covariance and the Conan et al. (1995)
    temporal asymptotes (an approximation of frozen flow, see the module docstring);
  - modalinfo kaos_like: the same at 4x oversampling plus the closed loop;
  - the route a user would take otherwise, hcipy: two InfiniteAtmosphericLayer screens
    (64 x 64 pixels over 0.7 m, r0 = 7 cm split 70/30, L0 = 20 m, 5 and 10 m/s) advanced
    frame by frame and projected on Z2..Z28 by least squares. That gives true frozen-flow
    statistics (wind direction, lagged cross-correlations) that the spectral model does
    not; it is timed over fewer frames and extrapolated linearly to 8000 (the per-frame
    cost is constant), with the layer construction timed separately.

Run: /work/venv/bin/python benchmarks/bench_synthetic.py [--repeats 5] [--hcipy-frames 400]
"""

import argparse
import time
import warnings

import numpy as np
from _common import median_time

from modalinfo.telemetry.synthetic import KAOS_LIKE_DEFAULTS, Layer, kaos_like, open_loop_log


def hcipy_route(n_frames, rate=2000.0):
    import hcipy

    d, n_pix, wavelength = 0.7, 64, 500e-9
    grid = hcipy.make_pupil_grid(n_pix, d)
    t0 = time.perf_counter()
    layers = [
        hcipy.InfiniteAtmosphericLayer(
            grid, hcipy.Cn_squared_from_fried_parameter(0.07, wavelength) * frac, L0=20.0,
            velocity=v, seed=i)
        for i, (frac, v) in enumerate([(0.7, 5.0), (0.3, 10.0)])
    ]
    t_init = time.perf_counter() - t0
    basis = hcipy.make_zernike_basis(28, d, grid, 1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        aperture = np.asarray(hcipy.circular_aperture(d)(grid)) > 0.5
    proj = np.linalg.pinv(np.asarray(basis.transformation_matrix)[aperture][:, 1:])
    out = np.empty((n_frames, 27))
    t0 = time.perf_counter()
    for k in range(n_frames):
        phase = 0.0
        for layer in layers:
            layer.t = k / rate
            phase = phase + np.asarray(layer.phase_for(wavelength))
        out[k] = proj @ phase[aperture]
    t_frames = time.perf_counter() - t0
    return t_init, t_frames / n_frames


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--hcipy-frames", type=int, default=400)
    args = parser.parse_args()
    layers = [Layer(**d) for d in KAOS_LIKE_DEFAULTS["layers"]]

    t_ours = median_time(
        lambda: open_loop_log(range(2, 29), n_frames=8000, rate=2000.0, diameter=0.7,
                              layers=layers, outer_scale=20.0, seed=0),
        args.repeats,
    )
    t_kaos = median_time(lambda: kaos_like(seed=0), args.repeats)
    t_init, t_frame = hcipy_route(args.hcipy_frames)
    t_hcipy = t_init + 8000 * t_frame
    print("8000 frames x 27 modes, 2 layers, 2 kHz")
    print(f"  modalinfo open_loop_log        {t_ours * 1e3:9.1f} ms (median of {args.repeats})")
    print(f"  modalinfo kaos_like (4x + loop) {t_kaos * 1e3:8.1f} ms")
    print(f"  hcipy screens + projection     {t_hcipy * 1e3:9.1f} ms "
          f"(init {t_init * 1e3:.0f} ms + {t_frame * 1e3:.2f} ms/frame x 8000, "
          f"from {args.hcipy_frames} frames)")
    print(f"  ratio hcipy / open_loop_log    {t_hcipy / t_ours:9.0f} x")


if __name__ == "__main__":
    main()
