"""fft_strehl (refined peak) against the PSF's largest FFT sample: CPU time and value.

``closedloop.optics.science.fft_strehl`` refines the largest local maxima of the
zero-padded FFT PSF off the grid (bounded Nelder-Mead on the PSF's Fourier sum, round 44
PART a, S18 / S47). The peer a user would write is the largest FFT sample itself,
``max |FFT(P e^{i phi})|^2 / (sum P)^2``: this script times both on the same residual
phases (median CPU time, ``time.process_time``, one untimed call first) and prints the
ratio, and beside the sample peak of an 8x finer grid (padding 32), the "continuous"
reference a user would otherwise buy with a larger FFT (timed too). Residuals:
Kolmogorov-spectrum screens (k^-11/6 amplitude, FFT-filtered here from a seeded
Generator) scaled to an RMS of 0.3 / 1 / 2 rad over a circular pupil of ``--n`` pixels, and
a pure tilt half a sample off the grid.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_fft_strehl.py --n 64 --repeats 5
"""

from __future__ import annotations

import json

import numpy as np
from _common import int_options, timed


def _sample_peak(phase: np.ndarray, mask: np.ndarray, padding: int) -> float:
    n = phase.shape[0] * padding
    field = np.zeros((n, n), dtype=np.complex128)
    field[: phase.shape[0], : phase.shape[1]] = np.where(mask, np.exp(1j * phase), 0.0)
    return float((np.abs(np.fft.fft2(field)) ** 2).max() / mask.sum() ** 2)


def main() -> None:
    parser = int_options(__doc__, n=64, repeats=5, padding=4, seed=3)
    args = parser.parse_args()

    from closedloop.optics.science import fft_strehl

    n = args.n
    y, x = np.mgrid[:n, :n] - (n - 1) / 2
    mask = np.hypot(x, y) <= n / 2
    rng = np.random.default_rng(args.seed)
    # Kolmogorov-like screen by FFT filtering (k^-11/6 amplitude), tip/tilt kept
    k = np.hypot(*np.meshgrid(np.fft.fftfreq(4 * n), np.fft.fftfreq(4 * n)))
    k[0, 0] = np.inf
    white = rng.standard_normal((4 * n, 4 * n)) + 1j * rng.standard_normal((4 * n, 4 * n))
    screen = np.real(np.fft.ifft2(white * k ** (-11 / 6)))[:n, :n]
    screen -= screen[mask].mean()
    cases = {f"kolmogorov {rms} rad": screen * rms / screen[mask].std()
             for rms in (0.3, 1.0, 2.0)}
    cases["tilt half a sample off"] = 2 * np.pi * 0.5 / (args.padding * n) * x
    rows = []
    for name, phase in cases.items():
        t_ours, ours = timed(lambda p=phase: fft_strehl(p, mask, padding=args.padding),
                             args.repeats, cpu=True)
        t_peer, peer = timed(lambda p=phase: _sample_peak(p, mask, args.padding),
                             args.repeats, cpu=True)
        t_fine, fine = timed(lambda p=phase: _sample_peak(p, mask, 32), args.repeats, cpu=True)
        rows.append({"case": name, "fft_strehl": round(ours, 4),
                     "sample_peak": round(peer, 4), "sample_peak_padding32": round(fine, 4),
                     "fft_strehl_cpu_s": round(t_ours, 4), "sample_peak_cpu_s": round(t_peer, 4),
                     "padding32_cpu_s": round(t_fine, 4),
                     "ratio_to_sample_peak": round(t_ours / t_peer, 1),
                     "ratio_to_padding32": round(t_ours / t_fine, 2)})
    print(json.dumps({"n": n, "padding": args.padding, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
