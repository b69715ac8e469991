"""Round 7 of issue 27's adversarial inputs (closedloop API): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 7, issue 27".

Reference: the documented contract of ``SimulationResult.load`` (a file that is not an
intact result is refused with a ValueError naming it; a format-3 file is verified
against its checksums) and of ``simulate`` (bad arguments refused before any frame).
"""

from __future__ import annotations

import h5py
import pytest

from closedloop import SimulationResult, simulate

from .conftest import small


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    config = small("kaos")
    path = tmp_path_factory.mktemp("r7") / "run.h5"
    simulate(config, 4 * config.loop.time_step, progress=False).save(path)
    return path


def _edited(saved, tmp_path, drop):
    path = tmp_path / "edited.h5"
    path.write_bytes(saved.read_bytes())
    with h5py.File(path, "a") as f:
        for name in drop:
            del f.attrs[name]
    return path


def test_a_checksummed_result_without_its_format_version_is_verified(saved, tmp_path):
    # e52: deleting format_version made a format-3 file read as an unverified format 1
    path = _edited(saved, tmp_path, ["format_version"])
    with pytest.raises(ValueError, match=r"corrupt closedloop result .* do not match"):
        SimulationResult.load(path)


def test_an_unchecked_result_without_its_version_is_refused(saved, tmp_path):
    # q15: a format-1 file (no checksum) lacking `version` stopped with h5py's KeyError
    path = _edited(saved, tmp_path, ["format_version", "sha256", "version"])
    with pytest.warns(UserWarning, match=r"format-1"), pytest.raises(
            ValueError, match=r"attribute\(s\) version missing"):
        SimulationResult.load(path)


def test_an_unchecked_intact_result_still_loads(saved, tmp_path):
    # the same edit without removing `version`: an old file, read with the warning
    path = _edited(saved, tmp_path, ["format_version", "sha256"])
    with pytest.warns(UserWarning, match=r"format-1"):
        assert SimulationResult.load(path).times.shape == SimulationResult.load(
            saved).times.shape


def test_a_callback_that_is_not_callable_is_refused_before_the_run():
    # q10: callback=5 stopped at frame 0 with "'int' object is not callable"
    config = small("kaos")
    with pytest.raises(TypeError, match=r"`callback` must be callable or None; got 5"):
        simulate(config, 4 * config.loop.time_step, progress=False, callback=5)
