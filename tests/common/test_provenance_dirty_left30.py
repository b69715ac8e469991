"""left30-prov (issue 27): a provenance record says when the source differs from its commit.

README "Provenance" said a closedloop result's ``git`` was HEAD even with edits not
committed. Every record (``provenance``, ``run_record``: closedloop results, forecast's
JSON and CSV, paper_figures' figures, export's MI_CLOOP card) now carries ``git`` as
``"<sha>-dirty"`` (git describe's convention) when the package's tracked source was
edited, and ``source_sha256``, comparable without Git.

References, all outside the code under test: ``git rev-parse HEAD`` and ``git status``
of a temporary ``git clone`` of this checkout; the coreutils pipeline
``find ... -name '*.py' | LC_ALL=C sort | xargs sha256sum | sha256sum`` for the
fingerprint; the clone's code run in a fresh interpreter (``PYTHONPATH`` = the clone)
for the record a run writes. No ``git`` on ``PATH``: an empty ``PATH``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import modalinfo
from modalinfo.common import provenance as prov

TOP = Path(modalinfo.__file__).resolve().parents[1]
PACKAGES = ("modalinfo", "closedloop", "paper_figures")

pytestmark = pytest.mark.skipif(
    shutil.which("git") is None or shutil.which("sha256sum") is None
    or not (TOP / ".git").exists(), reason="needs git, sha256sum and a git checkout")


def _git(*args, cwd) -> str:
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True,
                          text=True).stdout.strip()


def _sha256sum_listing(root: Path) -> str:
    """The fingerprint as a shell computes it (the pipeline source_sha256 documents)."""
    names = " ".join(p for p in PACKAGES if (root / p).is_dir())
    out = subprocess.run(
        ["sh", "-c", f"find {names} -name '*.py' | LC_ALL=C sort | xargs sha256sum "
                     "| sha256sum"],
        cwd=root, check=True, capture_output=True, text=True,
        env={**os.environ, "LC_ALL": "C"}).stdout
    return out.split()[0]


@pytest.fixture(scope="module")
def clone(tmp_path_factory) -> Path:
    """A clone of this checkout whose HEAD holds the code under test, edits included."""
    dest = tmp_path_factory.mktemp("clone") / "repo"
    _git("clone", "-q", str(TOP), str(dest), cwd=TOP)
    for name in PACKAGES:  # this worktree's files, so the clone runs the code under test
        shutil.copytree(TOP / name, dest / name, dirs_exist_ok=True,
                        ignore=shutil.ignore_patterns("__pycache__"))
    _git("add", "-A", "--", *PACKAGES, cwd=dest)
    if _git("status", "--porcelain", "--untracked-files=no", cwd=dest):
        _git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "wt",
             cwd=dest)
    return dest


def test_clean_clone_records_its_commit_and_the_sha256sum_listing(clone):
    assert _git("status", "--porcelain", "--untracked-files=no", cwd=clone) == ""
    head = _git("rev-parse", "HEAD", cwd=clone)
    assert prov.git_describe(clone) == head  # no "-dirty"
    assert prov.source_sha256(clone) == _sha256sum_listing(clone)
    prov._code_record.cache_clear()
    assert prov.code_record(clone) == {"git": head,
                                       "source_sha256": _sha256sum_listing(clone)}


def test_edited_source_is_dirty_with_another_fingerprint(clone):
    head = _git("rev-parse", "HEAD", cwd=clone)
    clean = prov.source_sha256(clone)
    target = clone / "closedloop" / "__init__.py"
    original = target.read_bytes()
    try:
        target.write_bytes(original + b"\n# an edit not committed\n")
        assert _git("status", "--porcelain", cwd=clone) != ""  # git agrees: dirty
        assert prov.git_describe(clone) == f"{head}-dirty"
        assert prov.source_sha256(clone) == _sha256sum_listing(clone) != clean
    finally:
        target.write_bytes(original)
    assert prov.git_describe(clone) == head
    assert prov.source_sha256(clone) == clean


def test_edits_outside_the_packages_source_are_not_dirty(clone):
    head = _git("rev-parse", "HEAD", cwd=clone)
    clean = prov.source_sha256(clone)
    readme = clone / "README.md"
    original = readme.read_bytes()
    untracked = clone / "modalinfo" / "scratch_left30.txt"
    try:
        readme.write_bytes(original + b"\nnotes\n")  # tracked, but not package source
        untracked.write_text("x")  # untracked: not tracked source, not a .py file
        assert prov.git_describe(clone) == head
        assert prov.source_sha256(clone) == clean
    finally:
        readme.write_bytes(original)
        untracked.unlink()


def test_no_git_on_path_gives_the_fingerprint_only(clone, tmp_path, monkeypatch):
    empty = tmp_path / "bin"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    assert shutil.which("git") is None
    prov._code_record.cache_clear()
    try:
        record = prov.code_record(clone)
    finally:
        prov._code_record.cache_clear()
    assert record["git"] is None  # an unchecked commit is not recorded as if clean
    monkeypatch.undo()
    assert record["source_sha256"] == _sha256sum_listing(clone)


def test_an_installed_copy_without_git_compares_by_fingerprint(clone, tmp_path):
    site = tmp_path / "site-packages"  # a wheel's layout: the packages, no .git
    for name in PACKAGES:
        shutil.copytree(clone / name, site / name)
    assert prov.git_describe(site) is None
    assert prov.source_sha256(site) == prov.source_sha256(clone)


def test_a_run_of_edited_code_records_dirty(clone):
    """The record a closedloop result writes, from the edited clone's own interpreter."""
    head = _git("rev-parse", "HEAD", cwd=clone)
    target = clone / "modalinfo" / "common" / "__init__.py"
    original = target.read_bytes()
    code = ("import json; from modalinfo.common.provenance import run_record; "
            "print(json.dumps(run_record({'a': 1}, 3)))")
    env = {**os.environ, "PYTHONPATH": str(clone)}
    try:
        target.write_bytes(original + b"\n# edited\n")
        out = subprocess.run([sys.executable, "-c", code], cwd=clone, env=env, check=True,
                             capture_output=True, text=True).stdout
        record = json.loads(out)
        assert record["git"] == f"{head}-dirty"
        assert record["source_sha256"] == _sha256sum_listing(clone)
    finally:
        target.write_bytes(original)
    out = subprocess.run([sys.executable, "-c", code], cwd=clone, env=env, check=True,
                         capture_output=True, text=True).stdout
    assert json.loads(out)["git"] == head


def test_every_record_carries_the_code_record_of_this_checkout():
    head = _git("rev-parse", "HEAD", cwd=TOP)
    edited = _git("status", "--porcelain", "--untracked-files=no", "--", *PACKAGES,
                  cwd=TOP) != ""
    expected = {"git": head + ("-dirty" if edited else ""),
                "source_sha256": _sha256sum_listing(TOP)}
    record = prov.run_record({"a": 1}, 1)
    assert {k: record[k] for k in expected} == expected
