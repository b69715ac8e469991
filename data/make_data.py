"""Regenerate the shipped logs of ``data/`` and check them bit for bit.

Two spectral KAOS-like logs (``modalinfo.telemetry.synthetic.kaos_like``) and one
closed-loop log of the ``closedloop`` simulator's ``kaos`` preset (single-conjugate AO,
frozen-flow layers, Shack-Hartmann with aliasing and noise; :func:`kaos_closedloop`).

Usage (from the repository root)::

    python data/make_data.py            # regenerate in memory, compare with the files
    python data/make_data.py --write    # (re)write the files, then compare

The comparison loads each shipped file with :func:`modalinfo.io.load` and requires the
coefficient arrays to be bit-identical (``numpy.array_equal`` on the raw bytes) and every
other field (modes, rate, units, wavelength, metadata) to be equal. Exit status 0 when
everything matches, 1 otherwise (with the largest difference printed).

Bit-identity holds on the same platform and library versions; the FFTs and the matrix
product of the generator may round differently on another CPU or BLAS (differences of
order 1e-16 relative), which this script reports instead of hiding. The closed-loop log
records the versions it was made with (``metadata["environment"]``), so a test can tell
a rounding difference from a changed simulator.
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from pathlib import Path

import numba
import numpy as np
import scipy

from modalinfo.io import load, save
from modalinfo.telemetry.synthetic import kaos_like

HERE = Path(__file__).resolve().parent
SEED = 0
N_FRAMES = 8000
FILES = {
    "kaos_like_closed_loop.npz": dict(n_frames=N_FRAMES, closed_loop=True, seed=SEED),
    "kaos_like_open_loop.npz": dict(n_frames=N_FRAMES, closed_loop=False, seed=SEED),
}
#: the closedloop log: preset, seed, frames kept and loop start-up frames discarded
KAOS_CLOSEDLOOP = "kaos_closedloop.npz"
KAOS_PRESET = "kaos"
KAOS_DISCARD = 200
#: metadata that records the run's environment, not the log (not compared)
ENVIRONMENT_KEY = "environment"


def environment() -> dict:
    """Versions that the bits of a simulated log depend on."""
    import platform

    return {"numpy": np.__version__, "scipy": scipy.__version__,
            "numba": numba.__version__, "machine": platform.machine(),
            "python": platform.python_version()}


def kaos_closedloop(n_frames: int = N_FRAMES, seed: int = SEED):
    """Return the closed-loop WFS residual log of the ``kaos`` preset, with its provenance.

    Runs ``closedloop.simulate(presets.get("kaos"), ...)`` without prediction for
    ``KAOS_DISCARD + n_frames`` frames and keeps the last ``n_frames`` of the DM's
    reconstructed residual (``dm0.residual``: Noll Zernikes Z2-Z28, rad at 500 nm,
    2 kHz). The metadata holds the preset's config, the seed, the command that makes the
    file, the frames discarded and the environment.
    """
    from closedloop import presets, simulate

    config = presets.get(KAOS_PRESET)
    total = KAOS_DISCARD + n_frames
    result = simulate(config, total * config.loop.time_step, seed=seed, progress=False)
    log = result.logs["dm0.residual"][KAOS_DISCARD:]
    return log.with_metadata(
        provenance={"command": "python data/make_data.py --write",
                    "library_call": (f"closedloop.simulate(closedloop.presets.get("
                                     f"'{KAOS_PRESET}'), {total} * 0.5e-3, seed={seed})"
                                     f".logs['dm0.residual'][{KAOS_DISCARD}:]"),
                    "preset": KAOS_PRESET, "discarded_frames": KAOS_DISCARD,
                    "closure_index": int(result.closure_index)},
        **{ENVIRONMENT_KEY: environment()})


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
        "metadata": ({k: v for k, v in shipped.metadata.items() if k != ENVIRONMENT_KEY},
                     {k: v for k, v in fresh.metadata.items() if k != ENVIRONMENT_KEY}),
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
    fresh = kaos_closedloop()
    if args.write:
        save(fresh, HERE / KAOS_CLOSEDLOOP, overwrite=True)
        print(f"{KAOS_CLOSEDLOOP}: written")
    ok &= compare(KAOS_CLOSEDLOOP, fresh)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
