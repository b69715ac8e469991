"""A closed pipe on stdout: the one rule, ``closed_pipe_discarded`` (fix49-c, item 6).

``_ClosedPipeTolerant.write`` / ``flush`` and ``paper_figures``' progress lines each
caught ``BrokenPipeError`` and called ``discard_stdout``; they now share
``modalinfo.common.cli.closed_pipe_discarded``. A guard of the behaviour kept (it passes
before and after the merge). Reference: the stream's own ``write`` raising
``BrokenPipeError`` as ``io`` raises it after the reader of a pipe exits, and
``os.devnull``.
"""

from __future__ import annotations

import io
import sys

from modalinfo.common.cli import _ClosedPipeTolerant


class _GonePipe(io.StringIO):
    def write(self, text):
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self):
        raise BrokenPipeError(32, "Broken pipe")


def test_a_closed_pipe_sends_stdout_to_devnull_and_the_run_goes_on(monkeypatch):
    gone = _GonePipe()
    monkeypatch.setattr(sys, "stdout", gone)
    tolerant = _ClosedPipeTolerant(gone)
    assert tolerant.write("line\n") == 5  # taken as written
    assert sys.stdout is not gone and sys.stdout.name == "/dev/null"
    sys.stdout.close()
    monkeypatch.setattr(sys, "stdout", gone)
    tolerant.flush()  # no error
    assert sys.stdout is not gone
    sys.stdout.close()
