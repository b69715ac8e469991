"""The archive plots and a threaded batch leave the caller's matplotlib backend (audit 10-state).

Reference: matplotlib's own state before the call (``matplotlib.get_backend()`` and
``rcParams``) and PNG signatures of the files written. ``plot_archive`` (run by
``analyse_archive`` in the caller's process) called ``matplotlib.use("Agg")``, which
switched a notebook's or a GUI's backend for the rest of the session.
"""

import matplotlib
import pytest

from modalinfo.batch.report import plot_archive


def test_backend_and_rcparams_unchanged(pdf_backend, tmp_path):
    rows = [dict(analysis="summary", status="ok", rms_total=1.0 + i, rate=1000.0 * (i + 1),
                 path=f"p{i}") for i in range(3)]
    rc = dict(matplotlib.rcParams)
    written = plot_archive(rows, tmp_path)
    assert [p.name for p in written] == ["archive_vs_rate.png"]
    assert written[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert matplotlib.get_backend() == "pdf"
    assert dict(matplotlib.rcParams) == rc


def test_threaded_batch_leaves_backend(pdf_backend, tmp_path):
    """``run_log_task`` called ``matplotlib.use("Agg")``; with a thread-based client the
    worker runs in this process, so a batch switched the caller's backend (issue 27)."""
    distributed = pytest.importorskip("distributed")
    import numpy as np

    from modalinfo.batch import analyse_archive
    from modalinfo.io import save
    from modalinfo.telemetry.log import ModalLog

    rng = np.random.default_rng(27)
    for i in range(2):
        save(ModalLog(rng.normal(size=(64, 3)), rate=500.0), tmp_path / f"log{i}.npz")
    rc = dict(matplotlib.rcParams)
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=":0") as client:
        result = analyse_archive(str(tmp_path / "*.npz"), "summary", tmp_path / "out",
                                 client=client, progress=False, plots=False)
    assert [r["status"] for r in result.rows] == ["ok", "ok"]
    assert matplotlib.get_backend() == "pdf"
    assert dict(matplotlib.rcParams) == rc
