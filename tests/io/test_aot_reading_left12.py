"""Reading one loop of a closedloop AOT export: memory checked first, only the loop's box read.

Issue 27, left12-export: ``modalinfo info --loop dm0`` on a 9.1 GB full-size export exited
2 (under an address-space cap astropy's mapping of the whole file failed: "does not fit
in the memory") and, without a cap, copied the loop's full-plane mode images (3.3 GB for
the ground mirror) before identifying them. References, outside the reader: the file's
arrays read with astropy and identified by
:func:`modalinfo.bases.identify.identify_zernike` on the corrector's mask (what the reader
must reproduce; :func:`modalinfo.bases.image_basis.basis_from_images` on them for
``read_aot_basis``), the file's size on disk (``os.path.getsize``), and the mirror's plane
and disc sizes of the built ``LoopModel``. The memory readings are replaced, not the
machine's.
"""

from __future__ import annotations

import os

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from astropy.io import fits  # noqa: E402

from closedloop import LoopModel, simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from modalinfo.bases import identify  # noqa: E402
from modalinfo.cli import main  # noqa: E402
from modalinfo.common import memory  # noqa: E402
from modalinfo.io import load  # noqa: E402
from modalinfo.io.files import LogFormatError  # noqa: E402

from ..closedloop.conftest import small  # noqa: E402


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    cfg = small("mcao3")  # altitude mirrors: planes wider than their discs
    model = LoopModel(cfg)
    run = simulate(cfg, 12 * cfg.loop.time_step, seed=1, model=model, progress=False)
    path = tmp_path_factory.mktemp("read") / "mcao3.fits"
    export_aot(run, path, model=model)
    return path, model


def _one_line(capsys, *needles):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err
    return err


@pytest.mark.parametrize("i", [0, 2])
def test_identification_reads_only_the_discs_box(exported, monkeypatch, i):
    path, model = exported
    dm = model.dms[i]
    n_p = model.geometry.planes[dm.plane].n
    with fits.open(path) as hdus:
        images = np.asarray(hdus[f"DM{i} MODES"].data, dtype=np.float64)
        mask = np.asarray(hdus[f"DM{i} PUPIL"].data) != 0
    assert images.shape == (dm.n_modes, n_p, n_p) and mask.sum() == dm.pixels.size
    reference = identify.identify_zernike(images, mask=mask)
    seen = []
    real = identify.identify_zernike

    def spy(arr, **kw):
        seen.append(np.shape(arr))
        return real(arr, **kw)

    monkeypatch.setattr(identify, "identify_zernike", spy)
    log = load(path, loop=f"dm{i}")
    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    box = (dm.n_modes, rows[-1] - rows[0] + 1, cols[-1] - cols[0] + 1)
    assert seen == [box] and box[1] * box[2] < n_p * n_p  # not the whole plane
    got = log.metadata["modes_identification"]
    assert got == reference.to_dict()


def test_reading_refused_when_the_loop_cannot_fit(exported, monkeypatch, capsys):
    path, _ = exported
    monkeypatch.setattr(memory, "available_memory_bytes", lambda: 1000.0)
    with pytest.raises(LogFormatError, match=r"reading loop 'dm0' .* needs about .* of memory"):
        load(path, loop="dm0")
    assert main(["info", str(path), "--loop", "dm0"]) == 2
    _one_line(capsys, "needs about", "available")


def test_file_larger_than_the_address_space_left_is_refused_by_name(exported, monkeypatch,
                                                                     capsys):
    path, _ = exported
    size = os.path.getsize(path)
    monkeypatch.setattr(memory, "address_space_left_bytes", lambda: size - 1.0)
    with pytest.raises(LogFormatError, match=r"memory-mapped whole .*ulimit -v"):
        load(path, loop="dm0")
    assert main(["info", str(path), "--loop", "dm0"]) == 2
    _one_line(capsys, "ulimit -v", "--no-mode-images")
    monkeypatch.setattr(memory, "address_space_left_bytes", lambda: float(size))
    assert load(path, loop="dm0").n_modes == 35


def test_basis_reads_only_the_discs_box(exported, monkeypatch):
    from modalinfo.bases import image_basis
    from modalinfo.io.aot import read_aot_basis

    path, model = exported
    dm = model.dms[2]
    with fits.open(path) as hdus:
        images = np.asarray(hdus["DM2 MODES"].data, dtype=np.float64)
        mask = np.asarray(hdus["DM2 PUPIL"].data) != 0
        diameter = None
    seen = []
    real = image_basis.basis_from_images

    def spy(arr, **kw):
        seen.append(np.shape(arr))
        nonlocal diameter
        diameter = kw["diameter"]
        return real(arr, **kw)

    monkeypatch.setattr(image_basis, "basis_from_images", spy)
    basis, _ = read_aot_basis(path, loop="dm2")
    n_p = model.geometry.planes[dm.plane].n
    assert len(seen) == 1 and seen[0][0] == dm.n_modes and seen[0][1] * seen[0][2] < n_p ** 2
    # the same basis as from the whole plane (its diameter aside: the file's telescope's)
    expected = real(images, mask=mask, diameter=diameter)
    np.testing.assert_array_equal(basis.matrix, expected.matrix)
    np.testing.assert_array_equal(basis.pupil.mask, expected.pupil.mask)
