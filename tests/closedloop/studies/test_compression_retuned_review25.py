"""Planted-bug review round 25 (review25, issue 27): the compression study's record of
the gains it retuned (round 38's ``_grid_runs`` returning them), which no test read.

Reference: ``gain_for_delay``' documented rule - at a delay where the preset's gain
keeps its gain margin it is kept (``changed`` False) and nothing is recorded; a delay
where it had to be lowered is recorded with the gain used. The study's delays are those
of ``test_study_grid_by_hand`` (0.5625, 0.625 and 0.6875 ms on the 0.0625 ms grid).
"""

import pytest

from closedloop.studies import compression as comp

from .test_mutation_gaps_compression import BP, BZ, _kaos6, recorder  # noqa: F401


@pytest.mark.parametrize("gain", [None, 0.9])
def test_retuned_gain_records_only_the_delays_whose_gain_changed(recorder, monkeypatch,  # noqa: F811
                                                                 gain):
    """R25-C5: the preset's gain (kept at every delay: nothing recorded) and a gain of
    0.9, lowered at the longer delays: exactly those, with their gains."""
    import dataclasses

    cfg = _kaos6()
    if gain is not None:
        cfg = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=gain))
    monkeypatch.setattr(comp, "control_orderings",
                        lambda ref, *, orderings, seed: {"zernike": BZ, "pca": BP})
    study = comp.compression_study(cfg, n_values=[4, 2], duration=0.02,
                                   orderings=["zernike", "pca"], predictor="linear-ls",
                                   seed=7)
    delays = {float(d) for v in study.delay.values() for d in v} - {cfg.loop.delay}
    assert delays  # the latency runs met new delays
    expected = {}
    for d in sorted(delays):
        loop, changed = comp.gain_for_delay(cfg.loop, d)
        if changed:
            expected[d] = loop.gain
    assert study.retuned_gain == pytest.approx(expected, rel=1e-12)
    if gain is not None:
        assert expected  # the case where a gain is lowered is met
