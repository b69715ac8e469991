"""A closedloop AOT export's loops read back with the modes and units they were written with.

Issue 27, leftovers 12-cli item 2: the pseudo-open-loop loop ``dm<i>.pol`` of an export
carried no mode images, so ``modalinfo info`` showed its Zernike modes "(assumed)".
References, outside the reader: the simulation's own logs (``run.logs["dm0.pol"]``: its
modes and units, what the export wrote), the mirror's controlled modes (``LoopModel``),
and astropy's listing of the file's image extensions (one ``MODES`` image, written once
and referenced by both loops).
"""

from __future__ import annotations

import dataclasses

import pytest

aotpy = pytest.importorskip("aotpy")

from astropy.io import fits  # noqa: E402

from closedloop import LoopModel, simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from modalinfo.cli import main as modalinfo_main  # noqa: E402
from modalinfo.io import load  # noqa: E402

from .conftest import small  # noqa: E402

KINDS = ("zernike", "actuators", "ideal")


@pytest.fixture(scope="module", params=KINDS)
def exported(request, tmp_path_factory):
    cfg = small("kaos")
    cfg = cfg.replace(dms=tuple(dataclasses.replace(d, kind=request.param) for d in cfg.dms))
    model = LoopModel(cfg)
    run = simulate(cfg, 12 * cfg.loop.time_step, seed=1, model=model, progress=False)
    path = tmp_path_factory.mktemp("aot") / f"{request.param}.fits"
    export_aot(run, path, model=model)
    return request.param, run, model, path


@pytest.mark.parametrize("uid,name", [("dm0", "residual"), ("dm0.pol", "pol")])
def test_each_loop_reads_back_its_modes_and_units_not_assumed(exported, uid, name, capsys):
    kind, run, model, path = exported
    log = load(path, loop=uid)
    ref = run.logs[f"dm0.{name}"]
    assert "assumed" not in log.metadata
    assert log.units == ref.units == "rad" and log.wavelength == ref.wavelength
    assert list(log.labels) == list(ref.labels)
    if kind == "zernike":  # Noll indices from the mode images, Z2.. as the mirror controls
        assert log.convention == "noll" and list(log.modes) == model.dms[0].modes
    assert modalinfo_main(["info", str(path), "--loop", uid]) == 0
    out = capsys.readouterr().out
    assert "(assumed)" not in out


def test_the_mode_images_are_written_once(exported):
    kind, _, model, path = exported
    with fits.open(path) as hdus:
        names = [h.name for h in hdus]
    images = [n for n in names if n.endswith(" MODES")]
    # a zonal ('ideal') mirror has no shape matrix: no images, its pixels named by a card
    assert images == ([] if model.dms[0].shapes is None else ["DM0 MODES"]), kind
