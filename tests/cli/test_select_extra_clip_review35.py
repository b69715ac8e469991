"""Mutation round 35 (review35): ``select --extra --outliers clip``'s one figure (fix52-c).

``cmd_select._check_memory`` takes the larger quality pass: ``--extra``'s, which runs
while LOG's clipped copy is held. tests/cli/test_select_extra_memory_round52.py reads it
under ``--outliers warn`` only, where nothing is held, and on two logs of one size, so
a check that dropped the held copy, or took LOG's pass, passed it.

Reference: bytes counted by hand. The first refusal's figure is the quality pass's (the
message says "the larger"); ``--outliers clip`` adds to ``--extra``'s pass (EXTRA of 6 or 8 modes,
LOG of 6: the larger pass, by LOG's held copy alone at 6) one float64 copy of EXTRA (the
repaired log) and LOG's repaired copy held meanwhile: 8 x 20,000 x (6 + 6) or (8 + 6)
bytes (1.831 or 2.136 MiB) over the same command under ``--outliers warn``. The figures are
printed to 0.01 MiB; the margin 0.02 MiB. The refusal names both files and their
shapes as written (each log's copies counted: "3 float64 copies each").
"""
from __future__ import annotations

import numpy as np
import pytest

from .test_memory_refusal_figure_round50 import _first_figure

_ARGV = ["select", "log.npy", "--extra", "extra.npy", "--rate", "1000", "--in-units", "rad",
         "--target", "Z2", "--max-lag", "1", "--surrogates", "19", "--no-intervals",
         "--method", "gaussian", "--outliers"]


def _two_logs(folder, extra_modes: int = 6) -> None:
    rng = np.random.default_rng(3512)
    np.save(folder / "log.npy", rng.standard_normal((20_000, 6)))
    np.save(folder / "extra.npy", rng.standard_normal((20_000, extra_modes)))


@pytest.mark.parametrize("extra_modes", [6, 8])
def test_clip_adds_extras_repaired_copy_and_logs_held_one(tmp_path, monkeypatch,
                                                          extra_modes):
    from modalinfo.cli import shared

    _two_logs(tmp_path, extra_modes)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(shared, "memory_available", lambda: 1.0)
    figures = {}
    for policy in ("warn", "clip"):
        figures[policy] = _first_figure(monkeypatch, [*_ARGV, policy])
    assert figures["clip"] - figures["warn"] == pytest.approx(8 * 20_000 * (extra_modes + 6),
                                                              abs=0.02 * 2**20)


def test_the_refusal_names_both_logs_and_each_ones_copies(tmp_path, monkeypatch, capsys):
    from modalinfo.cli import main, shared

    _two_logs(tmp_path, extra_modes=4)
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(shared, "memory_available", lambda: 1.0)
    assert main([*_ARGV, "warn"]) == 2
    err = capsys.readouterr().err
    assert "'log.npy' and 'extra.npy' (20000 frames x 6 + 4 modes, 3 float64 copies each, " \
           "and --max-lag 1's 10 candidate columns)" in err, err
