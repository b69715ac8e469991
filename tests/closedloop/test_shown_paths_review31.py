r"""closedloop's refusals quote the file in its shown form (review 31, round 31 mutation).

``tests/io/test_shown_paths_fix48a.py`` reaches ``load_config`` and ``load_grid`` through
one bad TOML; a raw ``'{path}'`` planted back in the empty-config refusal, the result
reader's folder refusal, ``export_aot``'s existing target or the CLI's suffix check
passed every test. References, outside the package: the file's bytes (``os.fsencode``)
and ``codecs.escape_decode`` of the quoted name (``ls -b``'s escapes back to bytes).
"""

from __future__ import annotations

import os

import pytest

from tests.io.test_shown_paths_fix48a import BYTE, SLASH, _names_file

STEMS = pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])


@STEMS
def test_an_empty_config(tmp_path, stem):
    from closedloop.config import load_config

    path = os.path.join(os.fsencode(tmp_path), stem + b".toml")
    open(path, "wb").close()
    with pytest.raises(ValueError) as caught:
        load_config(os.fsdecode(path))
    assert "is empty" in str(caught.value) and _names_file(str(caught.value), path)


@STEMS
def test_a_result_that_is_a_folder(tmp_path, stem):
    from closedloop.result import SimulationResult

    path = os.path.join(os.fsencode(tmp_path), stem + b".h5")
    os.mkdir(path)
    with pytest.raises(IsADirectoryError) as caught:
        SimulationResult.load(os.fsdecode(path))
    assert _names_file(str(caught.value), path), ascii(str(caught.value))


@STEMS
def test_an_aot_export_onto_an_existing_file(tmp_path, stem):
    from closedloop.aot import export_aot

    path = os.path.join(os.fsencode(tmp_path), stem + b".fits")
    open(path, "wb").close()
    with pytest.raises(FileExistsError) as caught:
        export_aot(None, os.fsdecode(path))  # refused before the result is read
    assert _names_file(str(caught.value), path), ascii(str(caught.value))


@STEMS
def test_the_clis_config_suffix_check(tmp_path, stem):
    from closedloop.cli import _check_config_suffix

    path = os.path.join(os.fsencode(tmp_path), stem + b".yaml")
    with pytest.raises(Exception) as caught:  # noqa: B017 - CommandError
        _check_config_suffix("--config", os.fsdecode(path))
    assert _names_file(str(caught.value), path), ascii(str(caught.value))


@STEMS
def test_a_grid_with_an_unknown_key(tmp_path, stem):
    from closedloop.sweep import load_grid

    path = os.path.join(os.fsencode(tmp_path), stem + b".toml")
    with open(path, "wb") as fh:
        fh.write(b'preset = "scao"\nbogus = 1\n')
    with pytest.raises(ValueError) as caught:
        load_grid(os.fsdecode(path))
    assert "unknown key `bogus`" in str(caught.value), str(caught.value)
    assert _names_file(str(caught.value), path), ascii(str(caught.value))
