"""The closure transient of an exported closed loop, read by ``modalinfo info`` (fix54-e).

Round 54 PART a (S30): every ``closedloop export`` residual showed the simulator's first
5-8 frames (the open-loop turbulence before the first command reached the mirror, then
the integrator's convergence) as outliers and "glitched frames" (kaos, 0.5 s, seed 1:
glitched frames 0, 1, 2, 4, 5). The result owns that number, ``averaging_start`` (the
frames before its steady state); the export writes it in the residual's ``MI_TRANS``
card, the reader puts it in ``metadata["transient_frames"]``, and the quality pass leaves
those frames out and says so.

References: the result's own ``averaging_start`` (read back through the FITS file), the
quality pass run by hand on the rows after the transient (the same flags, shifted: a
round trip), and a glitch planted here (every mode +40 robust sigmas at frame 600, after
the transient) that the report must still name as a glitched frame. The tests fail
before fix54-e: the export had no card, and ``info`` named glitched frames 0-5.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

pytest.importorskip("aotpy")

from closedloop import presets, simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from modalinfo.cli import main as modalinfo_main  # noqa: E402
from modalinfo.io import load  # noqa: E402
from modalinfo.telemetry import apply_outlier_policy, assess_quality  # noqa: E402

GLITCH = 600


@pytest.fixture(scope="module")
def run():
    return simulate(presets.get("kaos"), 0.5, seed=1, progress=False)


@pytest.fixture(scope="module")
def exported(run, tmp_path_factory):
    folder = tmp_path_factory.mktemp("transient")
    clean = folder / "clean.fits"
    export_aot(run, clean)
    log = run.logs["dm0.residual"]
    x = np.array(log.coeffs)
    sigma = 1.4826 * np.median(np.abs(x - np.median(x, axis=0)), axis=0)
    x[GLITCH] += 40.0 * sigma
    glitched = dataclasses.replace(run, logs={**run.logs,
                                              "dm0.residual": log._derive(_coeffs=x)})
    planted = folder / "planted.fits"
    export_aot(glitched, planted)
    return clean, planted


def test_export_carries_the_results_transient(run, exported):
    assert run.averaging_start > 0
    log = load(exported[0], loop="dm0")
    assert log.metadata["transient_frames"] == run.averaging_start
    assert "transient_frames" not in load(exported[0], loop="dm0.pol").metadata


def test_info_names_no_glitch_in_the_transient(run, exported, capsys):
    assert modalinfo_main(["info", str(exported[0]), "--loop", "dm0", "--quiet"]) == 0
    captured = capsys.readouterr()
    quality = next(line for line in captured.out.splitlines() if line.startswith("quality"))
    assert "glitched" not in quality
    t = run.averaging_start
    assert f"frames 0-{t - 1} not assessed: the loop's closure transient" in quality
    report = assess_quality(load(exported[0], loop="dm0"))
    assert report.transient_frames == t
    assert not np.any(report.flagged_frames < t)
    assert report.glitch_frames.size == 0


def test_a_planted_glitch_after_the_transient_is_named(exported, capsys):
    assert modalinfo_main(["info", str(exported[1]), "--loop", "dm0", "--quiet"]) == 0
    captured = capsys.readouterr()
    quality = next(line for line in captured.out.splitlines() if line.startswith("quality"))
    assert f"1 glitched frame(s) with outliers in >= 3 modes ({GLITCH})" in quality
    log = load(exported[1], loop="dm0")
    report = assess_quality(log)
    np.testing.assert_array_equal(report.glitch_frames, [GLITCH])
    # the same flags as the pass run by hand on the rows after the transient, shifted back
    t = report.transient_frames
    by_hand = assess_quality(log[t:].with_metadata(transient_frames=0))
    np.testing.assert_array_equal(report.flagged_frames, by_hand.flagged_frames + t)
    np.testing.assert_array_equal(report.outliers, by_hand.outliers)
    # clip repairs the glitch and leaves the transient as it is; drop keeps its frames
    clipped, _ = apply_outlier_policy(log, "clip")
    np.testing.assert_array_equal(clipped.coeffs[:t], log.coeffs[:t])
    assert not np.array_equal(clipped.coeffs[GLITCH], log.coeffs[GLITCH])
    dropped, _ = apply_outlier_policy(log, "drop")
    assert dropped.n_frames == log.n_frames - report.n_flagged
    np.testing.assert_array_equal(dropped.coeffs[:t], log.coeffs[:t])
