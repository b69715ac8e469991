"""Figure 1's report on a user's ``--log`` is true of that log (round 33 PART b, B31).

References, outside the code: what panel (c) is, by construction - ``compute`` draws it
from ``kaos_like(closed_loop=False, seed=0)`` whatever the log (the module docstring;
``test_mutation_gaps_fig1_fitting_error`` checks the call), so for a user's log it is not
"the same turbulence" and no open-vs-closed-loop verdict can rest on it; what a log is,
by its own metadata (``loop``, ``coefficient_quantity``, as ``modalinfo info`` reads
them); and the counts of the tables beside each sentence (a ``Figure1`` written by hand
in ``test_mutation_gaps_fig1_fitting_error``: the Reading below is worked out from its
numbers). The shipped logs' text is pinned there, word for word, and did not move. The
``--outliers`` policy and its counts reach Figures 1 and 5's reports (they were on
stderr only), in the words of the command line's stderr line.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from modalinfo.telemetry import ModalLog
from paper_figures import fig1_fitting_error as fig1
from paper_figures import fig5_forecast as fig5
from paper_figures._common import SYNTHETIC_SOURCE, outlier_records

from .test_main_report_text import _save, figs  # noqa: F401  (figs: a fixture)
from .test_mutation_gaps_fig1_fitting_error import _figure, _panel
from .test_mutation_gaps_fig5_forecast import _figure as _figure5

SHIPPED_ONLY = ("same turbulence", "consistent with the paper's interpretation",
                "closed-loop log", "synthetic", "K-L advantage is", "our closed-loop")

# worked out from _figure()'s numbers: typical (20, 14, 6, 12, 5), sample medians MI
# Zernike 21, MI K-L 8, a_k^2 9; pooled (20, 17, 18, 16, 19); open (20, 8, 14, 7, 13);
# spread 2.34; orthonormality 0.031
READING = (
    "**Reading.** On the typical frame the MI-ordered Zernikes need 6 modes and the "
    "MI-ordered K-L 14 to reach the error the standard order reaches with 20 (paper: 7 and "
    "15). Over 15 frames spread through the log the medians are 21 (MI Zernike) and 8 "
    "(MI K-L): per-frame MI reordering needs more than the standard 20 for Zernikes and "
    "fewer than 20 for K-L on this log. The per-frame a_k^2 order needs 5 modes on the "
    "typical frame (median 9); for an orthonormal basis it is the exact per-frame optimum "
    "(the error is the sum of the dropped a_k^2; our 64-pixel Zernikes are orthonormal to "
    "3%), so it, not the standard order, is the baseline a per-frame reordering has to "
    "beat: MI order does not beat it here. Averaged over frames (pooled orderings) the "
    "orderings need 16-20 modes (MI Zernike 18, MI K-L 17, data-PCA floor 16, standard "
    "order 20) on this log, whose mode variances span a factor 2.3 (max/min mean-square "
    "coefficient). Panel (c) is not this log's turbulence: it is the package's KAOS-like "
    "open-loop log `kaos_like(closed_loop=False, seed=0)` (2000 frames), shown for "
    "reference, where the MI-ordered theoretical K-L needs 8 modes and the data-PCA 7, "
    "against 20 for standard Zernikes (MI Zernikes 14); its turbulence is unrelated to "
    "this log's, so the two are not compared. Differences from the paper's numbers are "
    "expected: this log is not the paper's 2008 VTT data; one \"typical\" frame is a "
    "choice (ours: median total variance), which is why the spread over frames is given; "
    "and the MI estimator, its binning and the pupil sampling are ours.\n")


def test_user_log_reading_word_for_word():
    text = fig1.report(_figure())  # source `my.npz`: a user's log
    assert READING in text
    for words in SHIPPED_ONLY:
        assert words not in text, words
    assert ("**(c) open loop, 2000 frames of the package's KAOS-like log "
            "`kaos_like(closed_loop=False, seed=0)`, not this log's turbulence**") in text
    assert ("**Targets.** The paper's 0.4 waves^2 is a level of its own VTT residual. The "
            "total variance dPhi(0) of this log is 0.047 waves^2 on average (0.052 on the "
            "typical frame), so 0.4 waves^2 is \"reached\" with 0 modes by every ordering "
            "on the typical frame.") in text
    # whichever way the open-loop counts fall, no verdict on two unrelated logs
    other = fig1.report(_figure(open_cal=(20, 17, 14, 7, 13)))
    assert "K-L advantage" not in other and "in closed loop" not in other
    # the shipped log keeps its words
    shipped = fig1.report(_figure(source=SYNTHETIC_SOURCE))
    assert "In open loop (same turbulence)" in shipped and READING not in shipped


def test_closed_loop_only_when_the_metadata_says_so():
    text = fig1.report(_figure(closed_loop=True))
    assert "total variance dPhi(0) of this closed-loop log is" in text
    assert "standard order 20) on this closed-loop log, whose" in text
    assert "same turbulence" not in text
    for meta, expected in (({}, None), ({"loop": "closed"}, True), ({"loop": "open"}, False),
                           ({"loop": "closed", "coefficient_quantity": "pol"}, False),
                           ({"loop": "closed", "coefficient_quantity": "residual"}, True)):
        log = ModalLog(np.zeros((3, 2)), modes=[2, 3], metadata=meta)
        assert fig1._closed_loop(log) is expected, meta


def test_targets_on_a_log_above_the_paper_level():
    # 0.4 waves^2 is not reached with 0 modes by every ordering: say the counts of table (a)
    f = _figure()
    big = dataclasses.replace(f, typical=_panel(3.1, 0.2, (5, 3, 2, 4, 1), (20, 14, 6, 12, 5)))
    text = fig1.report(big)
    assert ("(3.1 on the typical frame); the orderings need 1-5 modes to reach 0.4 waves^2 "
            "on the typical frame (table (a)).") in text
    assert '"reached" with 0 modes' not in text


def test_the_outlier_policy_is_in_the_report():
    said = ("--outliers clip: 1 of 300 frames flagged: 1 outlier value(s); clipped 1 "
            "outlier value(s)")
    text = fig1.report(_figure(outliers=said))
    assert f"(horizontal line).\n\n**Outliers.** {said}.\n\n**Targets.**" in text
    assert "**Outliers.**" not in fig1.report(_figure())  # none applied: nothing said
    text5 = fig5.report(dataclasses.replace(_figure5(), outliers=said))
    assert f"\n\n**Outliers.** {said}.\n\n- (a) Linear predictor" in text5
    assert "**Outliers.**" not in fig5.report(_figure5())
    # a log clipped by the library carries its record: compute states it by default
    x = np.random.default_rng(0).standard_normal((400, 3))
    log = ModalLog(x, modes=[2, 3, 4], metadata={"outliers": [
        {"policy": "clip", "action": "clipped 2 outlier value(s)"}]})
    assert outlier_records(log) == "--outliers clip: clipped 2 outlier value(s)"
    assert outlier_records(ModalLog(x, modes=[2, 3, 4])) == ""


def test_paper_figures_passes_the_policy_and_counts(figs, tmp_path):  # noqa: F811
    from paper_figures.__main__ import main

    seen = []

    def compute(log, *, source, outliers=None):
        seen.append(outliers)
        return "r"

    figs.mods["fig1_fitting_error"].compute = compute
    x = np.random.default_rng(1).normal(size=(300, 6)) * 0.01
    x[100, 2] = 1.0  # one outlier, 100 sigma
    log = _save(tmp_path / "out.npz", x, rate=2000.0)
    assert main(["--only", "1", "--log", str(log), "--outliers", "clip",
                 "--out", str(tmp_path / "o")]) == 0
    (said,) = seen
    assert said.startswith("--outliers clip: 1 of 300 frames flagged: 1 outlier value(s)")
    assert "; clipped 1 outlier value(s)" in said
    x[100, 2] = x[99, 2]  # clean now
    clean = _save(tmp_path / "clean.npz", x, rate=2000.0)
    assert main(["--only", "1", "--log", str(clean), "--out", str(tmp_path / "p")]) == 0
    assert seen[1].startswith("--outliers warn: 0 of 300 frames flagged by ")
    assert seen[1].endswith("; nothing to act on")
