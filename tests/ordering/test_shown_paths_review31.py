r"""ordering's file refusals quote the file shown (review 31, round 31 mutation).

A raw ``'{path}'`` planted back in ``OrderingResult.from_json``'s invalid-JSON refusal or
in ``compare.save_figure``'s existing-file refusal passed every test. References,
outside the package: the file's bytes (``os.fsencode``) and ``codecs.escape_decode`` of
the quoted name (``ls -b``'s escapes back to bytes).
"""

from __future__ import annotations

import os

import pytest

from tests.io.test_shown_paths_fix48a import BYTE, SLASH, _names_file

STEMS = pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])


@STEMS
def test_an_ordering_that_is_not_json(tmp_path, stem):
    from modalinfo.ordering.result import OrderingResult

    path = os.path.join(os.fsencode(tmp_path), stem + b".json")
    with open(path, "wb") as fh:
        fh.write(b"{")
    with pytest.raises(ValueError) as caught:
        OrderingResult.from_json(os.fsdecode(path))
    assert _names_file(str(caught.value), path), ascii(str(caught.value))


@STEMS
def test_a_figure_onto_an_existing_file(tmp_path, stem):
    from modalinfo.ordering.compare import save_figure

    path = os.path.join(os.fsencode(tmp_path), stem + b".png")
    open(path, "wb").close()
    with pytest.raises(FileExistsError) as caught:
        save_figure(None, os.fsdecode(path))  # refused before the figure is used
    assert _names_file(str(caught.value), path), ascii(str(caught.value))
