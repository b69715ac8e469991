"""``modalinfo reorder --frame K --method standard`` is refused: the standard order is one.

Round 49 PART b, D57: ``reorder small.npz --frame 3 --method standard`` printed "zernike
basis, standard order (frame 3)", a per-frame claim of an order no frame changes (the
reference: Noll's numbering, the same Z2, Z3, ... whatever the data), while ``--seed``,
``--budget`` and ``--estimator`` with ``--method standard`` and ``--frame`` with
``--method pca`` are refused. ``--frame`` with ``--method variance`` stays accepted (the
squared coefficients of frame K order differently from frame to frame).
"""

from __future__ import annotations

import numpy as np

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog


def _log(path):
    x = np.random.default_rng(0).normal(size=(50, 5)) * np.array([1, 3, 2, 5, 4]) * 0.1
    save(ModalLog(x, modes=[2, 3, 4, 5, 6], units="rad", rate=1000.0), path)
    return str(path)


def test_frame_with_the_standard_order_is_refused(tmp_path, capsys):
    log = _log(tmp_path / "log.npz")
    code = main(["reorder", log, "--frame", "3", "--method", "standard",
                 "--pupil-pixels", "16"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "--frame 3" in err and "--method standard" in err and "drop --frame" in err, err


def test_frame_with_the_variance_order_runs(tmp_path, capsys):
    log = _log(tmp_path / "log.npz")
    code = main(["reorder", log, "--frame", "3", "--method", "variance",
                 "--pupil-pixels", "16"])
    assert code == 0, capsys.readouterr().err
