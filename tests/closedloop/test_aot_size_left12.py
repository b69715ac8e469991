"""The AOT export's size estimate and its refusals (issue 27, left12-export).

A full-size ``est-mcao-solar`` export wrote 9.1 GB: the mirrors' mode images, ``(M, n_p,
n_p)`` float64 over each mirror's whole plane (8.9 GB of it, computed from the config).
References, outside the estimate: the written file's size on disk (``os.path.getsize``),
and the mode images' bytes computed by hand from the built ``LoopModel`` (modes x plane
side squared x 8 B) and listed by astropy (the ``MODES`` extensions' header sizes).
The refusals are checked with the memory (available memory, address space left under a
``ulimit -v``) and disk readings replaced, not the machine's.
"""

from __future__ import annotations

import dataclasses
import os

import pytest

aotpy = pytest.importorskip("aotpy")

from astropy.io import fits  # noqa: E402

from closedloop import LoopModel, simulate  # noqa: E402
from closedloop.aot import estimate_aot, export_aot  # noqa: E402
from closedloop.cli import main as closedloop_main  # noqa: E402
from closedloop.resources import ResourceError  # noqa: E402
from modalinfo.common import folders, memory  # noqa: E402
from modalinfo.common.folders import OutputError  # noqa: E402

from .conftest import small  # noqa: E402

CASES = ("kaos-zernike", "kaos-actuators", "kaos-ideal", "mcao3")


def _config(case: str):
    if case == "mcao3":
        return small("mcao3")  # three mirrors: the joint reconstructor's cross blocks
    cfg = small("kaos")
    kind = case.split("-")[1]
    return cfg.replace(dms=tuple(dataclasses.replace(d, kind=kind) for d in cfg.dms))


@pytest.fixture(scope="module", params=CASES)
def run(request, tmp_path_factory):
    cfg = _config(request.param)
    model = LoopModel(cfg)
    result = simulate(cfg, 12 * cfg.loop.time_step, seed=1, model=model, progress=False)
    return result, model, tmp_path_factory.mktemp("size")


def _image_bytes_by_hand(model) -> float:
    return sum(8.0 * dm.n_modes * model.geometry.planes[dm.plane].n ** 2
               for dm in model.dms if dm.shapes is not None)


@pytest.mark.parametrize("images", [True, False])
def test_estimate_matches_the_file_on_disk(run, images):
    result, model, folder = run
    path = export_aot(result, folder / f"images-{images}.fits", model=model,
                      mode_images=images, overwrite=True)
    size = estimate_aot(result, model=model, mode_images=images)
    real = os.path.getsize(path)
    # headers and padding are estimated (2.5 blocks per extension, 60 for the tables):
    # within 5 % or 40 blocks of 2880 B on these small files
    assert abs(size.file_bytes - real) <= max(0.05 * real, 40 * 2880)
    by_hand = _image_bytes_by_hand(model) if images else 0.0
    assert size.parts["mode_images"] == by_hand
    with fits.open(path) as hdus:
        listed = sum(h.size for h in hdus[1:] if h.name.endswith(" MODES"))
    assert listed == by_hand


@pytest.mark.parametrize("reading", ["available_memory_bytes", "address_space_left_bytes"])
def test_refused_under_a_small_memory_reading(run, monkeypatch, reading):
    result, model, folder = run
    size = estimate_aot(result)  # the model rebuilt: counted
    assert size.memory_bytes > estimate_aot(result, model=model).memory_bytes
    monkeypatch.setattr(memory, reading, lambda: size.memory_bytes - 1)
    target = folder / "refused.fits"
    with pytest.raises(ResourceError, match=r"needs about .* of memory") as info:
        export_aot(result, target)
    if size.parts["mode_images"] > 0:
        assert "mode_images=False" in str(info.value)
    assert not target.exists()


def test_refused_when_the_disk_lacks_the_file(run, monkeypatch):
    result, model, folder = run
    size = estimate_aot(result, model=model)
    monkeypatch.setattr(folders, "writable_free_bytes", lambda f: size.file_bytes / 2)
    target = folder / "nodisk.fits"
    with pytest.raises(OutputError, match="is needed"):
        export_aot(result, target, model=model)
    assert not target.exists()


def test_cli_refuses_in_one_line_and_names_the_option(run, monkeypatch, capsys):
    result, model, folder = run
    if estimate_aot(result).parts["mode_images"] == 0:
        pytest.skip("a zonal mirror writes no mode images")
    saved = folder / "run.h5"
    if not saved.exists():
        result.save(saved)
    size = estimate_aot(result)
    monkeypatch.setattr(memory, "available_memory_bytes", lambda: size.memory_bytes - 1)
    target = folder / "cli.fits"
    assert closedloop_main(["export", str(saved), str(target)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--no-mode-images" in err and "Traceback" not in err
    assert not target.exists()
    # without the images the estimate is under the reading: written
    lean = estimate_aot(result, mode_images=False)
    assert lean.memory_bytes < size.memory_bytes - 1
    assert closedloop_main(["export", str(saved), str(target), "--no-mode-images"]) == 0
    with fits.open(target) as hdus:
        assert not any(h.name.endswith(" MODES") for h in hdus)
