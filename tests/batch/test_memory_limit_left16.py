"""Leftovers 16-dask (issue 27), limit L4: ``batch`` out of memory under ``ulimit -v``.

Under ``ulimit -v 1 GB`` a batch said "out of memory: realloc of size 128 failed; use a
smaller log or smaller options", naming neither the address-space limit nor the local
workers it binds. Now the line names ``RLIMIT_AS``'s value and ``--workers``.

Reference from outside the code: the standard library's ``resource.getrlimit``
(monkeypatched to report a 1 GiB soft ``RLIMIT_AS`` at the moment of the failure, as
``ulimit -v 1048576`` would; every other resource passed through) and the exact size
1 GiB = 1024**3 bytes.
"""

from __future__ import annotations

import resource

import pytest

import modalinfo.batch

GIB = 1024**3


def _fail_under(monkeypatch, limit):
    real = resource.getrlimit

    def fake(which):
        return (limit, resource.RLIM_INFINITY) if which == resource.RLIMIT_AS else real(which)

    def analyse_archive(*_args, **_kwargs):
        monkeypatch.setattr(resource, "getrlimit", fake)  # only once the work started
        raise MemoryError("realloc of size 128 failed")

    monkeypatch.setattr(modalinfo.batch, "analyse_archive", analyse_archive)


@pytest.mark.parametrize("extra, workers", [([], True), (["--scheduler", "tcp://h:8786"], False)])
def test_the_address_space_limit_and_the_workers_are_named(tmp_path, capsys, monkeypatch,
                                                            extra, workers):
    from modalinfo.cli import main

    _fail_under(monkeypatch, GIB)
    (tmp_path / "a.npz").write_bytes(b"")
    code = main(["batch", str(tmp_path / "a.npz"), "--out", str(tmp_path / "out"), *extra])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "out of memory: realloc of size 128 failed" in err
    assert "ulimit -v" in err and "RLIMIT_AS" in err and "1.00 GiB" in err
    assert ("--workers 1" in err) is workers  # a remote cluster sets its own workers


def test_without_a_limit_the_workers_are_still_named(tmp_path, capsys, monkeypatch):
    from modalinfo.cli import main

    _fail_under(monkeypatch, resource.RLIM_INFINITY)
    (tmp_path / "a.npz").write_bytes(b"")
    code = main(["batch", str(tmp_path / "a.npz"), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "ulimit" not in err and "--workers 1" in err
