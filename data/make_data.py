"""Regenerate the shipped synthetic logs of ``data/`` and check them bit for bit.

Usage (from the repository root)::

    python data/make_data.py            # regenerate in memory, compare with the files
    python data/make_data.py --write    # (re)write the files, then compare

The comparison loads each shipped file with :func:`modalinfo.io.load` and requires the
coefficient arrays to be bit-identical (``numpy.array_equal`` on the raw bytes) and every
other field (modes, rate, units, wavelength, metadata) to be equal. Exit status 0 when
everything matches, 1 otherwise (with the largest difference printed).

Bit-identity holds on the same platform and library versions; the FFTs and the matrix
product of the generator may round differently on another CPU or BLAS (differences of
order 1e-16 relative), which this script reports instead of hiding.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from pathlib import Path

import numpy as np

from modalinfo.io import load, save
from modalinfo.telemetry.synthetic import kaos_like

HERE = Path(__file__).resolve().parent
SEED = 0
N_FRAMES = 8000
FILES = {
    "kaos_like_closed_loop.npz": dict(n_frames=N_FRAMES, closed_loop=True, seed=SEED),
    "kaos_like_open_loop.npz": dict(n_frames=N_FRAMES, closed_loop=False, seed=SEED),
}


def digest(arr: np.ndarray) -> str:
    """SHA-256 of the little-endian float64 bytes of ``arr`` (C order)."""
    return hashlib.sha256(np.ascontiguousarray(arr, dtype="<f8").tobytes()).hexdigest()


def compare(name: str, fresh) -> bool:
    """Return True if the shipped file ``name`` holds exactly ``fresh``."""
    path = HERE / name
    if not path.exists():
        print(f"{name}: MISSING (run with --write)")
        return False
    shipped = load(path)
    same_bits = (shipped.coeffs.shape == fresh.coeffs.shape
                 and np.ascontiguousarray(shipped.coeffs, dtype="<f8").tobytes()
                 == np.ascontiguousarray(fresh.coeffs, dtype="<f8").tobytes())
    fields = {
        "modes": (shipped.modes, fresh.modes),
        "rate": (shipped.rate, fresh.rate),
        "units": (shipped.units, fresh.units),
        "wavelength": (shipped.wavelength, fresh.wavelength),
        "convention": (shipped.convention, fresh.convention),
        "metadata": (shipped.metadata, fresh.metadata),
    }
    bad_fields = [k for k, (a, b) in fields.items() if a != b]
    if same_bits and not bad_fields:
        print(f"{name}: bit-identical ({fresh.n_frames} x {fresh.n_modes}, "
              f"sha256 {digest(fresh.coeffs)[:16]}...)")
        return True
    if not same_bits:
        if shipped.coeffs.shape != fresh.coeffs.shape:
            print(f"{name}: DIFFERENT shape {shipped.coeffs.shape} vs {fresh.coeffs.shape}")
        else:
            diff = np.max(np.abs(np.asarray(shipped.coeffs) - fresh.coeffs))
            print(f"{name}: DIFFERENT coefficients (max |difference| {diff:.3g} rad)")
    if bad_fields:
        print(f"{name}: DIFFERENT fields {bad_fields}")
    return False


def main(argv: list[str] | None = None) -> int:
    """Regenerate (and with ``--write`` rewrite) the files; return the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", action="store_true", help="(re)write the shipped files")
    args = parser.parse_args(argv)
    ok = True
    for name, kwargs in FILES.items():
        fresh = kaos_like(**kwargs)
        if args.write:
            save(fresh, HERE / name, overwrite=True)
            print(f"{name}: written")
        ok &= compare(name, fresh)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
