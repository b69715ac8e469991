"""``closedloop config --out`` into a folder it cannot write in: one line naming the path.

Round 40 PART b F12: ``closedloop config --preset kaos --out ro/c.toml`` in a read-only
mount ended in "closedloop config: error: [Errno 30] Read-only file system:
'.../ro/.c.toml.21588-s_hl6h8z.tmp'" - the temporary file's name, not the user's path,
where ``run --out`` / ``export`` / ``modalinfo convert`` say "cannot write in 'ro'".
Reference: the file system itself - ``/proc`` takes no new files (ENOENT on create,
also as root), so the refusal must name ``--out``, the path and its folder, and no
temporary name; nothing is written.
"""

import sys

import pytest

from closedloop.cli import main

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc is Linux's")


@pytest.mark.parametrize("name, extra", [("c.toml", []), ("c.json", ["--overwrite"])])
def test_config_out_in_an_unwritable_folder_names_the_folder(capsys, name, extra):
    code = main(["config", "--preset", "kaos", "--out", f"/proc/{name}", *extra])
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert f"--out '/proc/{name}': cannot write in '/proc'" in err, err
    assert ".tmp" not in err and "Errno" not in err, err
