"""Fixtures of the batch tests: a 2-process LocalCluster per file and a small mixed archive.

The archive holds 47 readable logs in five formats (written with ``modalinfo.io.save``
and ``numpy.save``) and 3 corrupt files (a truncated NPZ, a FITS file with a garbage
header, an empty HDF5 file).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.telemetry.log import ModalLog

FORMATS = ("npz", "csv", "fits", "h5", "npy")
N_GOOD = 47
CORRUPT = ("broken.npz", "broken.fits", "empty.h5")
DAY = 86400.0
EPOCH = 1.78e9  # 2026-05-28


def make_log(i: int, n_frames: int = 256, n_modes: int = 6) -> ModalLog:
    """An AR(1) log per index: smooth enough to forecast, with date and seeing."""
    rng = np.random.default_rng(1000 + i)
    phi = 0.9 + 0.005 * (i % 10)
    x = np.zeros((n_frames, n_modes))
    noise = rng.normal(size=(n_frames, n_modes)) / np.arange(1, n_modes + 1)
    for t in range(1, n_frames):
        x[t] = phi * x[t - 1] + noise[t]
    return ModalLog(x, rate=500.0 + 50 * (i % 4), modes=list(range(2, 2 + n_modes)),
                    convention="noll", units="rad", wavelength=5e-7,
                    start_time=EPOCH + i * DAY, metadata={"r0_m": 0.05 + 0.002 * i})


def write_archive(root, n_good: int = N_GOOD, corrupt: bool = True) -> dict:
    """Write the archive into ``root``; return {file name: source log or None}."""
    from modalinfo.io import save

    files = {}
    for i in range(n_good):
        fmt = FORMATS[i % len(FORMATS)]
        log = make_log(i)
        name = f"log{i:03d}.{fmt}"
        if fmt == "npy":
            np.save(root / name, log.coeffs)
        else:
            save(log, root / name)
        files[name] = log
    if corrupt:
        good_npz = (root / "log000.npz").read_bytes()
        (root / CORRUPT[0]).write_bytes(good_npz[: len(good_npz) // 2])
        (root / CORRUPT[1]).write_bytes(b"SIMPLE  =" + b"\x00garbage" * 40)
        (root / CORRUPT[2]).write_bytes(b"")
        files.update(dict.fromkeys(CORRUPT))
    return files


@pytest.fixture(scope="session")
def helpers():
    """The archive writers, for tests that need their own archive."""
    from types import SimpleNamespace

    return SimpleNamespace(make_log=make_log, write_archive=write_archive, CORRUPT=CORRUPT,
                           N_GOOD=N_GOOD)


@pytest.fixture(scope="session")
def archive(tmp_path_factory):
    root = tmp_path_factory.mktemp("archive")
    return root, write_archive(root)


@pytest.fixture(scope="module")
def client():
    """A real LocalCluster of 2 worker processes x 1 thread, opened as the CLI opens it.

    Module scope, not session: an idle cluster's processes keep polling (about 5 s of
    CPU per 30 s, measured on the 2-core machine), so one kept open until the end of
    the run costs more than opening one per test file that uses it (two files).
    """
    pytest.importorskip("distributed")
    from modalinfo.batch.engine import open_client

    with open_client(n_workers=2, threads_per_worker=1, memory_limit="1GB",
                     dashboard_address=None) as c:
        yield c


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """One 400 x 6 white log (Z2..Z7, rad, 500 Hz): the unused-option refusals' folder."""
    from modalinfo.io import save

    root = tmp_path_factory.mktemp("logs")
    x = np.random.default_rng(0).normal(size=(400, 6)) / np.arange(1, 7)
    save(ModalLog(x, rate=500.0, modes=list(range(2, 8)), convention="noll", units="rad",
                  wavelength=5e-7), root / "a.npz")
    return root
