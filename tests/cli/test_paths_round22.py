"""Round 22 PART b: paths no local file can have are refused at parse time.

Reference: POSIX path rules from outside the code - a URL scheme (RFC 3986 ``scheme:``),
a Windows drive or UNC prefix, an empty string and a component longer than
``os.pathconf(..., "PC_NAME_MAX")`` bytes name no local file here. Each is refused in one
line naming the argument, exit 2, and nothing is written.
"""
from __future__ import annotations

import os

import numpy as np
import pytest

from modalinfo.cli import main


@pytest.fixture()
def log(tmp_path):
    rng = np.random.default_rng(0)
    path = tmp_path / "a.npz"
    np.savez(path, coeffs=rng.standard_normal((200, 3)), rate=np.float64(1000.0))
    return path


def _limit() -> int:
    return os.pathconf(".", "PC_NAME_MAX")


@pytest.mark.parametrize("out, word", [
    ("C:\\out\\b.npz", "Windows path"),
    ("s3://bucket/b.npz", "URL"),
    ("", "empty path"),
])
def test_convert_out_refused_naming_argument(log, tmp_path, monkeypatch, capsys, out, word):
    monkeypatch.chdir(tmp_path)
    before = sorted(os.listdir(tmp_path))
    with pytest.raises(SystemExit) as exc:
        main(["convert", str(log), out])
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert err.count("\n") == 1 and "argument OUT" in err and word in err
    assert sorted(os.listdir(tmp_path)) == before  # nothing written


@pytest.mark.parametrize("path, word", [
    ("file:///tmp/a.npz", "URL"),
    ("https://example.com/a.npz", "URL"),
    ("x" * 300 + ".npz", "bytes"),
])
def test_info_log_refused_naming_argument(tmp_path, monkeypatch, capsys, path, word):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(["info", path])
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert "argument LOG" in err and word in err and "Errno" not in err
    if word == "URL":
        assert path in err  # quoted as typed, its '//' not folded


def test_local_names_still_read(log, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    name = "y" * (_limit() - 4) + ".npz"  # exactly at the limit
    (tmp_path / name).write_bytes(log.read_bytes())
    assert main(["info", name]) in (0, None)
    assert "3 modes" in capsys.readouterr().out
