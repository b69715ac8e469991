"""The source fingerprint of task keys keys on the code, not on comments or docstrings.

Reference: edits whose meaning is known from the language itself. A comment, blank
lines, or a docstring's text do not change what Python executes (the interpreter's own
``ast`` of the edited module equals the original's less docstrings); a one-token change
of a constant (``0.9`` -> ``0.91``) does. Before left15-misc the fingerprint was the
SHA-256 of the sources' bytes, so the first two edits changed it too and a resumed batch
or sweep ran every task again.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import shutil
from pathlib import Path

import pytest

from modalinfo.common.tasks import keys

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def copy(tmp_path_factory):
    root = tmp_path_factory.mktemp("src")
    for name in ("modalinfo", "closedloop"):
        shutil.copytree(ROOT / name, root / name, ignore=shutil.ignore_patterns("__pycache__"))
    return root


def _fingerprint(root: Path, monkeypatch) -> str:
    def find_spec(name, *args, **kwargs):  # the packages of ``root``, not the installed ones
        spec = importlib.machinery.ModuleSpec(name, None, is_package=True)
        spec.submodule_search_locations = [str(root / name)]
        return spec

    monkeypatch.setattr(importlib.util, "find_spec", find_spec)
    try:
        return keys.source_fingerprint.__wrapped__()
    finally:
        monkeypatch.undo()


def _edit(path: Path, old: str, new: str) -> str:
    text = path.read_text()
    assert text.count(old) == 1, old
    path.write_text(text.replace(old, new))
    return text


def test_comment_and_docstring_edits_keep_the_fingerprint_a_constant_changes_it(copy, monkeypatch):
    first = _fingerprint(copy, monkeypatch)
    presets = copy / "closedloop" / "presets.py"
    sweep = copy / "closedloop" / "sweep.py"
    original_presets = presets.read_text()
    original_sweep = sweep.read_text()
    try:
        # a comment, blank lines, a docstring reworded: the same code
        _edit(presets, "EST_MODES_PER_SUBAPERTURE = 0.9\n",
              "\n\n# a comment about the next line\nEST_MODES_PER_SUBAPERTURE = 0.9  # why\n")
        _edit(sweep, '    """Return the list index of a dotted key\'s part',
              '    """Return (reworded, in a new release) the list index of a dotted key\'s part')
        assert _fingerprint(copy, monkeypatch) == first
        # one token of code: another fingerprint
        _edit(presets, "EST_MODES_PER_SUBAPERTURE = 0.9  # why\n",
              "EST_MODES_PER_SUBAPERTURE = 0.91  # why\n")
        assert _fingerprint(copy, monkeypatch) != first
    finally:
        presets.write_text(original_presets)
        sweep.write_text(original_sweep)


@pytest.mark.parametrize("edit", [
    ("x = 1\n", "x = 2\n"),  # a constant
    ("x = 1\n", "y = 1\n"),  # a name
    ("def f():\n    return 'a'\n", "def f():\n    return 'b'\n"),  # a string that is no docstring
    ('def f():\n    "doc"\n    return 1\n', 'def f():\n    return 1\n    "doc"\n'),  # order
    ("", "import os\n"),  # a statement added
])
def test_any_code_change_changes_the_module_digest(edit):
    before, after = edit
    assert keys._code_digest(before.encode()) != keys._code_digest(after.encode())


@pytest.mark.parametrize("edit", [
    ("x = 1\n", "x = 1  # one\n\n\n"),
    ('"""Module."""\nx = 1\n', '"""Another text\n\nof the module."""\nx = 1\n'),
    ("class A:\n    'd'\n    x = (1,\n         2)\n", "class A:\n    x = (1, 2)\n"),
])
def test_layout_comment_and_docstring_keep_the_module_digest(edit):
    before, after = edit
    assert keys._code_digest(before.encode()) == keys._code_digest(after.encode())


def test_source_that_does_not_parse_is_keyed_on_its_bytes():
    assert keys._code_digest(b"def (:\n") != keys._code_digest(b"def (:\n#\n")
