"""``reorder --basis file`` on an export without mode images names the option (fix55-c).

Adversarial round 54 PART b, P23: ``closedloop export --no-mode-images`` leaves the
mirrors' mode images out, and ``reorder --basis file`` on that file said "has no mode
images" without saying why. Reference: the export's own option (``mode_images=False``)
and the ``MI_CLOOP`` card of the AOT file, read back with aotpy.
"""

import json

import pytest

from closedloop import simulate
from closedloop.aot import CLOSEDLOOP_KEY, export_aot
from modalinfo.cli import main
from modalinfo.io.aot import _no_images_reason

from .conftest import tiny_actuator_config

aotpy = pytest.importorskip("aotpy")


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return simulate(tiny_actuator_config(), 0.005, seed=0)


def test_the_refusal_names_the_option(run, tmp_path, capsys):
    out = export_aot(run, tmp_path / "nomi.fits", mode_images=False)
    card = next(m.value for m in aotpy.AOSystem.read_from_file(str(out)).metadata
                if m.key == CLOSEDLOOP_KEY)
    assert json.loads(card)["mode_images"] is False
    assert main(["reorder", str(out), "--loop", "dm0.pol", "--basis", "file",
                 "--method", "variance", "--resamples", "0"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "has no mode images" in err
    assert "--no-mode-images" in err and "export the result again without that option" in err


def test_an_export_with_images_says_true(run, tmp_path):
    out = export_aot(run, tmp_path / "mi.fits")
    card = next(m.value for m in aotpy.AOSystem.read_from_file(str(out)).metadata
                if m.key == CLOSEDLOOP_KEY)
    assert json.loads(card)["mode_images"] is True


class _System:
    def __init__(self, notes):
        self.metadata = [aotpy.Metadatum(CLOSEDLOOP_KEY, json.dumps(notes))]


def test_an_older_export_names_the_option_as_the_likely_cause():
    assert "--no-mode-images" in _no_images_reason(_System({"written_by": "closedloop"}))
    assert _no_images_reason(_System({"written_by": "other"})) == ""
    assert _no_images_reason(_System({"written_by": "closedloop", "mode_images": True})) == ""
