"""``python -m paper_figures`` with a standard output that refuses its lines.

Adversarial round 38 PART b, row P48 (cause W2): ``paper_figures --only 1 --quick --out
pf48 > /dev/full`` said "No space left on device writing 'pf48' (nothing was written);
free space or write elsewhere": the disk was not full, standard output was (its first
progress line failed inside the staged output folder, whose error renaming took any
ENOSPC for the folder's). Reference: /dev/full's contract (every write fails with
ENOSPC, nothing else is full) and POSIX's rule that a closed pipe (``| head -1``) is the
reader's choice, not a failure of the work: the figures are the outputs.
"""

import os
import sys

from paper_figures.__main__ import main


class _Full:
    """A stream like /dev/full."""

    def write(self, text):
        raise OSError(28, "No space left on device")

    def flush(self):
        raise OSError(28, "No space left on device")


def test_a_full_stdout_is_named_as_stdout_not_the_output_folder(tmp_path, monkeypatch,
                                                                 capsys):
    out = tmp_path / "pf"
    monkeypatch.setattr(sys, "stdout", _Full())
    code = main(["--only", "1", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 1
    assert err.count("\n") == 1
    assert "could not write standard output (No space left on device)" in err
    assert f"'{out}' is as it was" in err
    assert "free space" not in err and "writing" not in err
    assert not out.exists()


def test_a_closed_pipe_on_a_progress_line_lets_the_run_go_on(monkeypatch):
    # before: the BrokenPipeError of the "done" line ended a 344 s run (exit 1, "error:
    # BrokenPipeError: Broken pipe; 'pf43c' is as it was": the figures discarded), P43
    from paper_figures.__main__ import _print

    read, write = os.pipe()
    os.close(read)  # the reader is gone, as after `| head -1`
    stream = os.fdopen(write, "w", encoding="utf-8")
    monkeypatch.setattr(sys, "stdout", stream)
    try:
        _print("[paper_figures] Figure 1: ... ")  # EPIPE: no exception reaches the run
        _print("[paper_figures] Figure 1 done")  # stdout now discards
    finally:
        stream.close()
