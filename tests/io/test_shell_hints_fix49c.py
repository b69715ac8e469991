r"""A suggested command line quotes a path as a shell word, to be pasted (fix49-c, item 3).

Fixes 48-a quoted every path through ``files.quoted`` (``ls -b``'s form, for reading),
also inside the command lines a refusal suggests: ``closedloop export 'a\xe9.h5'
OUT.fits`` for a file whose name holds the byte 0xE9 named, pasted, the file ``a\xe9.h5``
(backslash, x, e, 9), and ``'it's.h5'`` ended its quote early (stop 55's note). The
reference is bash itself: ``bash -c 'printf %s WORD'`` prints the name's bytes
(``os.fsencode``).
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess

import numpy as np
import pytest

from modalinfo.common.files import check_readable, shell_quoted
from modalinfo.io import load

NAMES = ["k.h5", "it's.h5", "a b$x`y`.h5", "a\\xe9.h5", os.fsdecode(b"a\xe9.h5"),
         "n\nl'q\t\x1b[1m.h5", "-dash.h5", "\u00e9t\u00e9 \u2028.h5"]


def _bash_word(word: str) -> bytes:
    bash = shutil.which("bash")
    if bash is None:
        pytest.skip("no bash")
    assert word.isprintable(), word  # one printable line
    done = subprocess.run([bash, "-c", f"printf %s {word}"], capture_output=True,
                          check=True, env={"LC_ALL": "C.UTF-8"}, timeout=60)
    return done.stdout


@pytest.mark.parametrize("name", NAMES)
def test_a_shell_word_gives_the_name_back(name):
    expected = os.fsencode(name if not name.startswith("-") else "./" + name)
    assert _bash_word(shell_quoted(name)) == expected


@pytest.mark.parametrize("name", NAMES)
def test_closedloop_export_hint_pastes(tmp_path, monkeypatch, name):
    h5py = pytest.importorskip("h5py")
    monkeypatch.chdir(tmp_path)
    with h5py.File(os.fsencode(name), "w") as f:
        f.attrs["format"] = "closedloop-result"
        f.create_dataset("x", data=np.zeros(3))
    with pytest.raises(Exception, match="is a closedloop result, not a log") as err:
        load(name)
    (word,) = re.findall(r"`closedloop export (.*) OUT\.fits`", str(err.value))
    assert _bash_word(word) == os.fsencode(("./" if name.startswith("-") else "") + name)


def test_batch_hint_for_a_folder_pastes(tmp_path):
    folder = tmp_path / os.fsdecode(b"d\n'\xe9")
    folder.mkdir()
    with pytest.raises(IsADirectoryError) as err:
        check_readable(folder)
    (word,) = re.findall(r"`modalinfo batch (.*) --out DIR`", str(err.value))
    assert _bash_word(word) == os.fsencode(folder)
