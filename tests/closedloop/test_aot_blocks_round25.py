"""Adversarial round 25 PART b, A4 / A6: reconstructor blocks of an AOT export are no logs.

Reference: the exporter's own record of each loop (the ``MI_CLOOP`` card, parsed with
``json`` from what ``aotpy.AOSystem.read_from_file`` reads) and the run's logs, bit for
bit, for the loops that do hold coefficients.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from closedloop import LoopModel, simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from modalinfo.io import load  # noqa: E402
from modalinfo.io.files import LogFormatError  # noqa: E402

from .conftest import small  # noqa: E402


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    cfg = small()
    model = LoopModel(cfg)
    run = simulate(cfg, 8 * cfg.loop.time_step, seed=2, model=model, progress=False)
    path = tmp_path_factory.mktemp("aot") / "run.fits"
    export_aot(run, path, model=model)
    return run, path


def test_a_reconstructor_block_is_refused_naming_the_logs(exported):
    run, path = exported
    system = aotpy.AOSystem.read_from_file(str(path))
    card = next(m.value for m in system.metadata if m.key == "MI_CLOOP")
    blocks = [uid for uid, said in json.loads(card)["loops"].items()
              if "no coefficients" in said]
    assert blocks  # the small config has a global reconstructor: dm0.wfs1, dm1.wfs0
    for uid in blocks:
        with pytest.raises(LogFormatError, match=rf"loop '{uid}' holds no coefficients.*"
                                                 r"'dm0', 'dm0.pol'"):
            load(path, loop=uid)
    # the loops with coefficients still read back bit for bit
    np.testing.assert_array_equal(load(path, loop="dm0").coeffs,
                                  run.logs["dm0.residual"].coeffs)
