"""Leftovers 17-sigint (issue 27): the Ctrl-C recorded while a Dask client lives.

Reference from outside the code: the signal as POSIX raises it (``signal.raise_signal``,
``raise(3)``, whose handler Python runs before the call returns), Python's documented
``signal.getsignal`` / ``signal.default_int_handler``; and the folder left on disk,
read with ``os.listdir``.
"""

from __future__ import annotations

import os
import signal
from types import SimpleNamespace

import pytest

from modalinfo.common.folders import locked_out_dir
from modalinfo.common.tasks.interrupts import raise_if_interrupted, sigint_deferred

posix = pytest.mark.skipif(not hasattr(signal, "raise_signal") or os.name != "posix",
                           reason="POSIX signals")


@posix
def test_a_sigint_is_recorded_then_raised_at_the_poll_and_the_handler_restored():
    before = signal.getsignal(signal.SIGINT)
    with pytest.raises(KeyboardInterrupt), sigint_deferred() as event:
        signal.raise_signal(signal.SIGINT)  # the handler ran: recorded, not raised
        assert event.is_set()
        with pytest.raises(KeyboardInterrupt):
            raise_if_interrupted(SimpleNamespace(modalinfo_interrupt=event))
        # a Ctrl-C after the last poll: raised on leaving the block
    assert signal.getsignal(signal.SIGINT) is before


@posix
def test_no_sigint_no_raise_and_another_error_stands():
    with sigint_deferred() as event:
        raise_if_interrupted(SimpleNamespace(modalinfo_interrupt=event))
        raise_if_interrupted(object())  # not a client of open_client: never raises
    with pytest.raises(ValueError, match="kept"), sigint_deferred():
        signal.raise_signal(signal.SIGINT)
        raise ValueError("kept")
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@posix
def test_an_ignored_sigint_stays_ignored():
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        with sigint_deferred() as event:
            assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        assert not event.is_set()
    finally:
        signal.signal(signal.SIGINT, before)


def test_a_new_folder_left_with_a_file_keeps_its_marker(tmp_path):
    out = tmp_path / "out"
    with locked_out_dir(out, "modalinfo batch"):
        (out / "rows").mkdir()
        (out / "hashes.json").write_text("{}")  # written before the first row
    assert sorted(os.listdir(out)) == ["hashes.json", "rows"]
    with locked_out_dir(out, "modalinfo batch"):  # the next run resumes there
        pass
    empty = tmp_path / "empty"
    with locked_out_dir(empty, "modalinfo batch"):
        (empty / "rows").mkdir()
    assert not empty.exists()  # a run that left nothing leaves no folder
