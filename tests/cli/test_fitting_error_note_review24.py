"""Planted-bug review 24 (issue 27): ``fitting-error``'s one note for the sampled bases.

Reference: the library's own ``PupilSamplingWarning`` s of the same comparison
(``compare_orderings`` on the same specs, log and pupil), one per basis, whose
differences ``test_fixes33a`` checks against the Parseval sum formed with numpy. The
command says one of them, the worst: the largest |difference| over the bases (here the
K-L's and the Zernikes' differ), with its n, the largest Gram error and the largest
suggested grid. Kolmogorov Zernikes 2..28 (Noll's covariance, 2000 seeded frames) on a
64-pixel pupil: Gram error 0.054, below the 0.1 of the Zernike note, above 0.01.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from modalinfo.bases import zernike_covariance
from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.ordering.compare import compare_orderings
from modalinfo.ordering.fitting_error import PupilSamplingWarning
from modalinfo.telemetry import ModalLog

MODES = np.arange(2, 29)
SPECS = "zernike:standard,kl-theory:variance"


def test_the_note_names_the_worst_basis(tmp_path, capsys):
    rng = np.random.default_rng(9)
    a = rng.standard_normal((2000, MODES.size)) @ np.linalg.cholesky(
        zernike_covariance(MODES)).T
    log = ModalLog(a, modes=MODES, units="rad", rate=1000.0, wavelength=5e-7)
    path = save(log, tmp_path / "k.npz")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        compare_orderings(log, SPECS, n_pixels=64)
    said = [w.message for w in caught if isinstance(w.message, PupilSamplingWarning)]
    assert len(said) == 2
    diffs = sorted(abs(w.difference) for w in said)
    assert f"{100 * diffs[0]:+.1f}" != f"{100 * diffs[1]:+.1f}"  # the two can be told
    worst = max(said, key=lambda w: abs(w.difference))
    assert main(["fitting-error", str(path), "--orderings", SPECS,
                 "--pupil-pixels", "64"]) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if "sampled bases are not orthonormal" in line]
    assert len(notes) == 1
    assert (f"up to {100 * worst.difference:+.1f} % (at {worst.n_at} modes)") in notes[0]
    gram = float(re.search(r"max \|gram - I\| ([0-9.]+)", notes[0]).group(1))
    assert gram == float(f"{max(w.gram_deviation for w in said):.2g}")
    assert f"--pupil-pixels {max(w.suggested_pixels for w in said)} " in notes[0]
