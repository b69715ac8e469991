"""An order whose noise was not assessed says so (round 33 PART b, B46 / B48 / B49).

Reference: construction. Tip and tilt drawn independently with the same variance have,
by symmetry, no preferred order: which comes first is a coin flip of the sample (the
round's log printed Z2 first on 4000 frames and Z3 first on its first half). Without a
bootstrap (``n_resamples`` 0) no rank can be marked '~' (within noise of the rank
above), so the legend may not say that '~' marks such ranks - it must say the noise was
not assessed and adjacent ranks may swap, once in the notes too, and the JSON must
record it (``noise_assessed``). With a bootstrap the '~' legend is the one that applies.
The ``reorder`` command line names its own flag (``--resamples``).
"""

import json

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.ordering import OrderingResult, order_modes
from modalinfo.ordering.compare import basis_for_log
from modalinfo.telemetry import ModalLog

TIE_LEGEND = "'~' before it: within noise of the rank above"


@pytest.fixture(scope="module")
def equal_pair():
    rng = np.random.default_rng(7)
    a = rng.standard_normal((300, 3)) * [1.0, 1.0, 0.3]  # Z2, Z3 equal variance; Z4 less
    log = ModalLog(a, rate=1000.0, modes=[2, 3, 4])
    return log, basis_for_log("zernike", log, n_pixels=16)


def test_no_resampling_says_noise_not_assessed(equal_pair, tmp_path):
    log, basis = equal_pair
    res = order_modes(log, basis, "mi_greedy", sample_budget=20_000, seed=0, n_resamples=0)
    assert set(res.labels[:2]) == {"Z2", "Z3"}  # the coin-flip pair leads
    assert res.noise_assessed is False and res.tied_with_previous is None
    legend = res.legend()
    assert TIE_LEGEND not in legend  # '~' cannot appear: the legend may not promise it
    assert "noise not assessed (n_resamples 0: no bootstrap)" in legend
    assert "adjacent ranks may swap within sampling noise" in legend
    notes = res.notes()
    assert sum("not assessed" in n for n in notes) == 1
    assert "n_resamples 40 or more" in notes[0]
    # the command line's words
    assert "(--resamples 0: no bootstrap)" in res.legend(resamples="--resamples")
    assert "--resamples 40 or more" in res.notes(resamples="--resamples")[0]
    record = res.to_dict()
    assert record["noise_assessed"] is False
    back = OrderingResult.from_json(res.to_json(tmp_path / "o.json"))
    assert back == res and back.noise_assessed is False


def test_with_resampling_the_tie_legend_applies(equal_pair):
    log, basis = equal_pair
    res = order_modes(log, basis, "mi_greedy", sample_budget=20_000, seed=0, n_resamples=40)
    assert res.noise_assessed is True and res.to_dict()["noise_assessed"] is True
    assert TIE_LEGEND in res.legend() and "not assessed" not in res.legend()
    assert not any("not assessed" in n for n in res.notes())


def test_baselines_without_bootstrap():
    log = ModalLog(np.random.default_rng(1).standard_normal((50, 3)), rate=100.0,
                   modes=[2, 3, 4])
    basis = basis_for_log("zernike", log, n_pixels=16)
    var = order_modes(log, basis, "variance")
    assert "(--method variance has no bootstrap)" in var.legend()
    assert TIE_LEGEND not in var.legend()
    (note,) = var.notes()
    assert "not assessed" in note and "n_resamples" not in note  # no flag that would help
    std = order_modes(log, basis, "standard")  # a convention: nothing to assess
    assert "not an estimate" in std.legend() and TIE_LEGEND not in std.legend()
    assert std.notes() == []


def test_reorder_command_says_it_and_records_it(equal_pair, tmp_path, capsys):
    log, _ = equal_pair
    path = tmp_path / "pair.npz"
    save(log, path)
    out = tmp_path / "o.json"
    assert main(["reorder", str(path), "--resamples", "0", "--pupil-pixels", "16",
                 "--budget", "20000", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert TIE_LEGEND not in printed
    said = "oise not assessed (--resamples 0: no bootstrap)"
    assert printed.count(said) == 2  # the legend, and one note
    assert "--resamples 40 or more" in printed
    assert json.loads(out.read_text())["noise_assessed"] is False
