r"""paper_figures' refusals quote the file shown (review 31, round 31 mutation).

A raw ``'{path}'`` planted back in the missing ``--log`` refusal (``python -m
paper_figures`` and the stand-alone scripts' ``_common.figure_main``) or in Figure 7's
existing-output refusal passed every test. References, outside the package: the file's
bytes (``os.fsencode``) and ``codecs.escape_decode`` of the quoted name (``ls -b``'s
escapes back to bytes); each refusal is one stderr line with status 2.
"""

from __future__ import annotations

import os

import pytest

from tests.io.test_shown_paths_fix48a import BYTE, SLASH, _names_file

STEMS = pytest.mark.parametrize("stem", [SLASH, BYTE], ids=["backslash", "byte"])


def _refusal(main, argv, capsys) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    return err


@STEMS
def test_a_missing_log_all_figures(tmp_path, stem, capsys):
    from paper_figures.__main__ import main

    log = os.path.join(os.fsencode(tmp_path), stem + b".npz")
    err = _refusal(main, ["--out", str(tmp_path / "out"), "--only", "1", "--log",
                          os.fsdecode(log)], capsys)
    assert "does not exist" in err and _names_file(err, log), ascii(err)


@STEMS
def test_a_missing_log_one_figure(tmp_path, stem, capsys):
    from paper_figures.fig1_fitting_error import main

    log = os.path.join(os.fsencode(tmp_path), stem + b".npz")
    err = _refusal(main, ["--out", str(tmp_path / "out"), "--log", os.fsdecode(log)], capsys)
    assert "does not exist" in err and _names_file(err, log), ascii(err)


@STEMS
def test_figure_7s_existing_output(tmp_path, stem, capsys):
    from paper_figures.fig7_solar import FIGURE_NAME, main

    out = os.path.join(os.fsencode(tmp_path), stem)
    os.mkdir(out)
    figure = os.path.join(out, os.fsencode(FIGURE_NAME))
    open(figure, "wb").close()
    err = _refusal(main, ["--out", os.fsdecode(out)], capsys)
    assert "exists" in err and _names_file(err, figure), ascii(err)


@STEMS
def test_an_oserror_reading_the_log_names_it_shown(tmp_path, stem, capsys, monkeypatch):
    """An ``OSError`` in Python's format (EIO) while reading ``--log``: the name shown."""
    import errno

    from modalinfo.cli import shared
    from paper_figures.__main__ import main

    log = os.path.join(os.fsencode(tmp_path), stem + b".npz")
    open(log, "wb").close()

    def eio(path, *args, **kwargs):
        raise OSError(errno.EIO, "Input/output error", os.fsdecode(log))

    monkeypatch.setattr(shared, "load_log_with_hints", eio)
    err = _refusal(main, ["--out", str(tmp_path / "out"), "--only", "1", "--log",
                          os.fsdecode(log)], capsys)
    assert "Input/output error" in err and _names_file(err, log), ascii(err)
