"""Round 32 (issue 27): ``source_sha256`` where there is no source to fingerprint.

Reference: ``hashlib.sha256(b"")`` (``e3b0c442...``), the SHA-256 of an empty
listing, which names no code; the packages imported from a zip file (``zipimport``,
a zipapp) in a fresh interpreter. Before the fix a folder that does not exist, an
empty folder, a file and a zipapp all gave that hash, and ``start=123`` raised an
unnamed ``TypeError`` from pathlib.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import modalinfo
from modalinfo.common import provenance as prov

TOP = Path(modalinfo.__file__).resolve().parents[1]
EMPTY = hashlib.sha256(b"").hexdigest()


@pytest.mark.parametrize("where", ["missing", "empty", "file"])
def test_a_start_without_the_packages_is_refused(tmp_path, where):
    start = {"missing": tmp_path / "nowhere", "empty": tmp_path,
             "file": TOP / "README.md"}[where]
    with pytest.raises(ValueError, match=r"^`start` = .* holds no \*\.py file of the packages"):
        prov.source_sha256(start)
    with pytest.raises(ValueError, match=r"^`start` = "):
        prov.code_record(start)


def test_a_start_that_is_not_a_path_is_named():
    with pytest.raises(TypeError, match=r"^`start` must be a folder path"):
        prov.source_sha256(123)


def test_a_zipapp_records_no_fingerprint_rather_than_the_empty_hash(tmp_path):
    archive = tmp_path / "modalinfo.zip"
    with zipfile.ZipFile(archive, "w") as z:
        for path in (TOP / "modalinfo").rglob("*.py"):
            z.write(path, path.relative_to(TOP).as_posix())
    code = ("import sys; sys.path.insert(0, sys.argv[1]); "
            "from modalinfo.common.provenance import code_record; "
            "print(code_record()['source_sha256'])")
    env = {**os.environ, "PYTHONPATH": ""}
    done = subprocess.run([sys.executable, "-c", code, str(archive)], capture_output=True,
                          text=True, env=env, cwd=tmp_path, timeout=120, check=True)
    assert done.stdout.strip() == "None"
    assert EMPTY not in done.stdout
