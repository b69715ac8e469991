"""Planted-bug review round 25 (review25, issue 27): ``reorder``'s unused-option guard
after it became one guard with ``fitting-error`` and ``batch`` (round 37 PART b, B04).

References: the refusals ``reorder`` printed before the shared guard, word for word
(round 13 / 17 PART b: "--method pca orders an empirical K-L basis of the same log;
--basis zernike is not one: use --basis kl-data, or --method variance"; since fold
40-a "--method pca with --basis zernike: pca orders ...", the words of the
``basis:method`` list's refusal), its rule that
``--resamples 0`` asks for no bootstrap (what variance does) and so is not refused,
and ``refuse_unused_arguments``' documented order: the first of
``MI_ONLY_ARGUMENTS`` (estimator, sample_budget, seed, n_resamples, ...) given is named.
"""

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def log_path(tmp_path):
    x = np.random.default_rng(36).standard_normal((300, 5)) / np.arange(1, 6)
    path = tmp_path / "log.npz"
    save(ModalLog(x, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad",
                  wavelength=5e-7), path)
    return path


def _refusal(argv, capsys):
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    return err.split("error: ", 1)[1].rstrip("\n")


def test_pca_on_a_model_basis_in_reorders_words(log_path, capsys):
    """R25-O5: the flags the user typed, --method and --basis, not another word."""
    said = _refusal(["reorder", str(log_path), "--method", "pca", "--basis", "zernike",
                     "--pupil-pixels", "24"], capsys)
    # one wording with the basis:method list's (fold 40-a)
    assert said == ("--method pca with --basis zernike: pca orders an empirical K-L basis "
                    "of the same log; zernike is not one: use --basis kl-data, or --method "
                    "variance")


def test_resamples_zero_with_variance_runs(log_path, capsys):
    """R25-O6: --resamples 0 asks for no bootstrap, which variance does: not refused."""
    code = main(["reorder", str(log_path), "--method", "variance", "--resamples", "0",
                 "--pupil-pixels", "24"])
    assert code == 0, capsys.readouterr().err


@pytest.mark.parametrize("extra, first", [
    (["--seed", "3", "--estimator", "ksg"], "--estimator"),
    (["--resamples", "100", "--budget", "1000"], "--budget"),
])
def test_the_first_unused_option_in_the_documented_order_is_named(log_path, capsys,
                                                                  extra, first):
    """R25-O2: several unused options: the first of MI_ONLY_ARGUMENTS given is named
    (whatever their order on the command line), the last one named before."""
    said = _refusal(["reorder", str(log_path), "--method", "variance", "--pupil-pixels",
                     "24", *extra], capsys)
    assert said == (f"{first} applies to the MI methods (mi_greedy, mi_marginal); "
                    "--method variance uses none: drop it")
