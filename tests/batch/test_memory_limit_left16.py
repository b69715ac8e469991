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


def test_workers_that_cannot_start_under_the_limit_are_one_line(tmp_path, capsys, monkeypatch):
    """L4b: ``ulimit -v 1 GB`` without ``-n``: the nanny's thread could not start.

    Reference: the exception chain and log record distributed 2026.8 produces then
    (``Nanny.instantiate`` logs "Failed to start process" with the traceback of
    ``RuntimeError: can't start new thread``, and ``LocalCluster`` raises "Nanny failed
    to start." from it), reproduced by a stand-in ``LocalCluster``.
    """
    import logging

    import distributed

    from modalinfo.cli import main

    class LocalCluster:
        def __init__(self, *_args, **_kwargs):
            try:
                try:
                    raise RuntimeError("can't start new thread")
                except RuntimeError:
                    logging.getLogger("distributed.nanny").exception("Failed to start process")
                    raise
            except RuntimeError as exc:
                raise RuntimeError("Nanny failed to start.") from exc

    monkeypatch.setattr(distributed, "LocalCluster", LocalCluster)
    seen: list[logging.LogRecord] = []

    class Keep(logging.Handler):
        def emit(self, record: logging.LogRecord) -> None:
            seen.append(record)

    logger = logging.getLogger("distributed.nanny")
    handler = Keep()
    logger.addHandler(handler)
    try:
        (tmp_path / "a.npz").write_bytes(b"")
        monkeypatch.setattr(resource, "getrlimit", lambda which: (
            (GIB, resource.RLIM_INFINITY) if which == resource.RLIMIT_AS
            else _REAL_GETRLIMIT(which)))
        code = main(["batch", str(tmp_path / "a.npz"), "--out", str(tmp_path / "out")])
        logger.error("another error")  # other records of the nanny are kept
    finally:
        logger.removeHandler(handler)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert "could not start its workers (can't start new thread)" in err
    assert "1.00 GiB" in err and "--workers 1" in err
    assert [r.getMessage() for r in seen] == ["another error"]


_REAL_GETRLIMIT = resource.getrlimit
