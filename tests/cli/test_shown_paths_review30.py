r"""More of fixes 47-b's refusals name a path in the shown form (review30, round 30).

Fixes 47-b quoted every message's path through ``modalinfo.common.files.quoted`` (a
literal backslash written ``\\``, an undecodable byte ``\xNN``, as GNU ``ls -b`` does);
tests/cli/test_shown_paths_fix47b.py reaches ``info`` and ``convert`` only. Planted slips
that wrote the raw path back at other call sites (``'{path}'`` for ``quoted(path)``:
review30 C2, D1, D2, L3, V3, V4, V5) passed every test. Reference: the ``ls -b`` form
written by hand (``d\\e`` for the name ``d\e``), ``codecs.escape_decode`` of each quoted
name giving the name's bytes back (``os.fsencode``), and the raw form absent.
"""

from __future__ import annotations

import codecs
import os
import re
from pathlib import Path

import pytest

from modalinfo.common.cli import CommandError, check_output
from modalinfo.common.folders import OutputError, check_room, locked_out_dir

from .conftest import exit_code, write_small_log

NAME = "d\\e"  # a backslash in a file or folder name
SHOWN = "d\\\\e"


def _quoted(text: str) -> list[bytes]:
    return [codecs.escape_decode(m.encode("utf-8"))[0] for m in re.findall(r"'([^']*)'", text)]


def _shown_only(text: str, *names: str) -> None:
    assert f"'{NAME}" not in text and f"/{NAME}" not in text, text
    found = _quoted(text)
    for name in names:
        assert os.fsencode(name) in found, (name, text)


def test_check_output_names_the_missing_folder_shown(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(CommandError) as err:
        check_output(Path(NAME) / "o.png", False, flag="--plot")
    _shown_only(str(err.value), f"{NAME}/o.png", NAME)
    assert f"directory '{SHOWN}' does not exist" in str(err.value)


def test_check_room_names_the_folder_shown(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    os.mkdir(NAME)
    with pytest.raises(OutputError) as err:
        check_room(Path(NAME), 1e30, "--out")
    _shown_only(str(err.value), NAME)
    assert f"is needed, '{SHOWN}' has" in str(err.value)


def test_a_foreign_folder_is_named_shown(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    os.mkdir(NAME)
    Path(NAME, "mine.txt").write_text("x")
    with pytest.raises(OutputError) as err, locked_out_dir(Path(NAME), "test"):
        pass
    _shown_only(str(err.value), NAME)
    assert f"output directory '{SHOWN}' is not empty" in str(err.value)


def test_closedloop_room_refusal_names_the_output_shown(tmp_path, monkeypatch):
    from closedloop.cli import _check_writable

    monkeypatch.chdir(tmp_path)
    os.mkdir(NAME)
    with pytest.raises(CommandError) as err:
        _check_writable(Path(NAME) / "r.h5", 1e30, "--out")
    _shown_only(str(err.value), f"{NAME}/r.h5", NAME)
    assert str(err.value).startswith(f"--out '{SHOWN}/r.h5': ")


def test_forecast_names_a_missing_log_and_an_existing_output_shown(tmp_path, monkeypatch,
                                                                   capsys):
    monkeypatch.chdir(tmp_path)
    assert exit_code(["forecast", NAME + ".npz"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"'{SHOWN}.npz'" in err, err
    _shown_only(err, NAME + ".npz")
    os.mkdir(NAME)
    Path(NAME, "forecast.json").write_text("{}")
    assert exit_code(["forecast", "missing.npz", "--out", NAME]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"'{SHOWN}/forecast.json' exists" in err, err
    _shown_only(err, f"{NAME}/forecast.json")


def test_select_max_frames_refusal_names_the_log_shown(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    log = write_small_log(tmp_path / (NAME + ".npz"), 400)
    assert exit_code(["select", str(log), "--target", "Z2", "--max-lag", "2",
                      "--no-intervals", "--surrogates", "9", "--alpha", "0.2", "--max-frames",
                      "12"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"frames of '{SHOWN}.npz'" in err, err
    _shown_only(err, NAME + ".npz")
