"""What the AOT export's loop cards say: mode labels (``MI_MODES``) and quantities (``MI_QUANT``).

References: ``aotpy.AOSystem.read_from_file`` (an independent reader of the file) for the
cards as written; the simulator's own mirror labels (``DeformableMirror.labels``: the
DM-space K-L modes ``DMKL1``..., what the result's logs carry) and the documented card
definitions of ``closedloop/aot.py``'s module docstring (``MI_QUANT`` ``residual`` or
``pol`` on each loop with coefficients; the reconstructor blocks ``dm{i}.wfs{k}`` have
no coefficient image, hence no card; ``MI_MODES`` only for modes that are not Noll
Zernikes, whose images ``modalinfo`` identifies itself); a hand-built system (aotpy
objects through ``modalinfo.io.aot_system``) for the reader's refusal of a bad card.
Cost: one 12-frame tiny actuator loop (~2 s of CPU) and the small MCAO export.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from closedloop import LoopModel, simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from modalinfo.io import LogFormatError, load  # noqa: E402
from modalinfo.io.aot import read_aot_basis, write_system  # noqa: E402
from modalinfo.io.aot_system import (  # noqa: E402
    CorrectorSpec,
    LoopSpec,
    SensorSpec,
    SourceSpec,
    build_system,
)

from .conftest import small  # noqa: E402


def _cards(image) -> dict:
    return {m.key: m.value for m in (getattr(image, "metadata", None) or [])}


@pytest.fixture(scope="module")
def kl_export(tiny_actuator_loop, tmp_path_factory):
    model = LoopModel(tiny_actuator_loop)
    run = simulate(tiny_actuator_loop, 12 * tiny_actuator_loop.loop.time_step, model=model,
                   progress=False)
    path = export_aot(run, tmp_path_factory.mktemp("kl") / "run.fits", model=model)
    return run, model, path


def test_dm_kl_labels_are_exported_and_read_back(kl_export):
    run, model, path = kl_export
    labels = list(model.dms[0].labels)
    assert labels[:2] == ["DMKL1", "DMKL2"] and len(labels) == model.dms[0].n_modes
    assert list(run.logs["dm0.residual"].modes) == labels
    system = aotpy.AOSystem.read_from_file(str(path))
    for uid, quantity in (("dm0", "residual"), ("dm0.pol", "pol")):
        lp = next(x for x in system.loops if x.uid == uid)
        cards = _cards(lp.modal_coefficients)
        assert json.loads(cards["MI_MODES"]) == labels  # aotpy reads the names as written
        assert cards["MI_QUANT"] == quantity
        log = load(path, loop=uid)  # not "mode1"...: the mirror's own names
        assert list(log.modes) == labels and log.convention == "labels"
    basis, _ = read_aot_basis(path, loop="dm0")
    assert list(basis.labels) == labels


def test_zernike_mirrors_carry_no_labels_and_blocks_no_quantity(tmp_path):
    cfg = small()
    model = LoopModel(cfg)
    assert model.reconstructor is not None  # global MAP: dm{i}.wfs{k} blocks exported
    run = simulate(cfg, 10 * cfg.loop.time_step, seed=2, model=model, progress=False)
    path = export_aot(run, tmp_path / "run.fits", model=model)
    system = aotpy.AOSystem.read_from_file(str(path))
    blocks = []
    for lp in system.loops:
        if lp.modal_coefficients is None:  # a reconstructor block: no image, no card
            blocks.append(lp.uid)
            continue
        cards = _cards(lp.modal_coefficients)
        assert cards["MI_QUANT"] == ("pol" if lp.uid.endswith(".pol") else "residual")
        assert "MI_MODES" not in cards  # Noll modes: identified from their images
    assert sorted(blocks) == ["dm0.wfs1", "dm1.wfs0"]
    assert list(load(path, loop="dm1").modes) == list(range(2, cfg.dms[1].n_modes + 2))


def _labelled_system(card):
    t = np.arange(8) * 1e-3
    coeffs = np.arange(16.0).reshape(8, 2)
    loop = LoopSpec("L", "W", "DM", modal_coefficients=coeffs, units="rad", timestamps=t,
                    framerate=1000.0, coefficient_metadata={"MI_MODES": card})
    return build_system([loop], sensors=[SensorSpec("W", "sun", 3)],
                        correctors=[CorrectorSpec("DM", 2)], sources=[SourceSpec("sun")])


def test_a_loop_without_mode_images_takes_the_cards_labels(tmp_path):
    path = write_system(_labelled_system('["KL-a","KL-b"]'), tmp_path / "ok.fits")
    log = load(path)
    assert list(log.modes) == ["KL-a", "KL-b"] and log.convention == "labels"


@pytest.mark.parametrize("card", ['["a"]', '["a","a"]', "not json", '{"a": 1}', '["a",""]'])
def test_a_bad_labels_card_is_refused_in_one_line(tmp_path, card):
    path = write_system(_labelled_system(card), tmp_path / "bad.fits")
    with pytest.raises(LogFormatError, match=r"loop 'L' card MI_MODES must be a JSON list of "
                                             r"2 distinct mode labels; got ") as exc:
        load(path)
    assert "\n" not in str(exc.value)
