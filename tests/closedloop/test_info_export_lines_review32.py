r"""``closedloop info`` / ``export`` report lines show the result's shown name (review32).

Planted-bug review of fix49-c (round 32): ``info``'s "RESULT: closedloop result ..."
line (R32-C6), ``export``'s "OUT: AOT system of ..." line (R32-C14) could print
the path raw (a newline splitting the line, ESC reaching the terminal) and pass every
test: the tests' results had plain names. Reference: ``files.shown_name``'s docstring
(``codecs.escape_decode`` of the shown form is the path's bytes), one printable line.
``io.formats.what_file``'s AOT hint used the reading form (R32-C11): ``shlex.split``.
"""

import codecs
import os

import pytest

from closedloop import simulate
from closedloop.cli import main
from closedloop.config import DMConfig, WFSConfig
from modalinfo.common.files import shown_name

from .conftest import small

pytest.importorskip("aotpy")


def _check(text: str, path) -> None:
    assert "\x1b" not in text, text
    shown = shown_name(path)
    (line,) = [x for x in text.splitlines() if x.startswith(shown + ": ")]
    assert line.isprintable(), line
    assert codecs.escape_decode(shown.encode("utf-8"))[0] == os.fsencode(path)


@pytest.mark.slow  # one simulation (numba compiles on a fresh machine)
def test_info_and_export_lines(tmp_path, capsys):
    base = small()
    c = base.replace(dms=(DMConfig(altitude=0.0, n_modes=9),),
                     wfss=(WFSConfig(altitude=0.0, field_of_view=base.wfss[0].field_of_view,
                                     kind="ideal", field_samples=1, dm=0),),
                     layers=base.layers[:1])
    h5 = tmp_path / "r\nu\x1b[1mn\u00e9.h5"
    simulate(c, 0.01, seed=1, progress=False).save(h5)
    assert main(["info", str(h5)]) == 0
    _check(capsys.readouterr().out, h5)
    out = tmp_path / "o\nu\x1b[1mt.fits"
    assert main(["export", str(h5), str(out)]) == 0
    _check(capsys.readouterr().out, out)
    # R32-C11: io.formats.what_file's hint for an AOT file, `modalinfo info PATH --loop
    # UID`, used quoted()'s reading form; reference: shlex.split gives the path back
    import re
    import shlex

    from modalinfo.io.formats import what_file

    aot = tmp_path / "it's.fits"
    assert main(["export", str(h5), str(aot)]) == 0
    (command,) = re.findall(r"`(modalinfo info [^`]*)`", what_file(aot))
    assert shlex.split(command)[2:] == [str(aot), "--loop", "UID"], command
