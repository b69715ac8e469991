"""A run that saves its result counts the HDF5 file it builds in memory, before any work.

References: the writer's own rule (``modalinfo.io.hdf5.image_bytes``, the bytes
``write_hdf5_file`` compares with the memory it may allocate to choose its path), the
estimate of the same run without saving (the two differ by exactly that part where the
run's phase makes the peak), and a ``simulate`` replaced by one that fails if called,
which shows a refusal came before any work. The result file's size estimate against a
real run: kaos 1 s, 2,671,500 bytes estimated, 2,659,051 written (docs/ADVERSARIAL.md,
"Leftovers 15-misc"). Before left15-misc ``closedloop run --out`` and ``config
--estimate`` did not count the file's image (one file's size of memory, 2 x 1.07 GiB
for table1 over 100 s).
"""

from __future__ import annotations

import pytest

import closedloop.simulation
import modalinfo.io.hdf5 as hdf5
from closedloop import presets
from closedloop.cli import main
from closedloop.resources import BASELINE_BYTES, estimate
from modalinfo.common.sizes import format_size


@pytest.fixture
def no_simulation(monkeypatch):
    def fail(*args, **kwargs):
        raise AssertionError("a simulation started")

    monkeypatch.setattr(closedloop.simulation, "simulate", fail)
    monkeypatch.setattr(closedloop.simulation, "LoopModel", fail)


def test_saving_adds_the_writers_image_of_the_file():
    config = presets.get("table1")
    plain, saved = estimate(config, 100.0), estimate(config, 100.0, save=True)
    image = hdf5.image_bytes(saved.file_bytes)
    assert image == hdf5.IMAGE_COPIES * saved.file_bytes > 0
    assert "hdf5_image" not in plain.parts and saved.parts["hdf5_image"] == image
    assert saved.run_bytes - plain.run_bytes == pytest.approx(image, rel=1e-12)
    # the run's phase makes both peaks here (100 s of logs), so the peaks differ by it
    assert plain.peak_bytes == pytest.approx(BASELINE_BYTES + plain.run_bytes, rel=1e-12)
    assert saved.peak_bytes - plain.peak_bytes == pytest.approx(image, rel=1e-12)
    assert plain.file_bytes == saved.file_bytes


def test_the_estimate_follows_the_writers_rule(monkeypatch):
    # one copy of the rule: the writer's constant changed, the estimate follows
    monkeypatch.setattr(hdf5, "IMAGE_COPIES", 3.0)
    saved = estimate(presets.get("kaos"), 1.0, save=True)
    assert saved.parts["hdf5_image"] == 3.0 * saved.file_bytes


def test_run_out_is_refused_before_work_when_the_image_does_not_fit(tmp_path, capsys,
                                                                     no_simulation,
                                                                     monkeypatch):
    config = presets.get("table1")
    plain, saved = estimate(config, 100.0), estimate(config, 100.0, save=True)
    limit = int((plain.peak_bytes + saved.peak_bytes) / 2)  # between the two
    out = tmp_path / "r.h5"
    code = main(["run", "--preset", "table1", "--duration", "100", "--out", str(out),
                 "--memory-limit", str(limit), "--quiet"])
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--memory-limit" in err, err
    assert f"needs about {format_size(saved.peak_bytes)}" in err, err
    assert not out.exists() and list(tmp_path.iterdir()) == []
    # without --out the same limit lets the run start (its check passed)
    import closedloop.training

    def started(*args, **kwargs):
        raise AssertionError("a simulation started")

    monkeypatch.setattr(closedloop.training, "run_trained", started)
    with pytest.raises(AssertionError, match="a simulation started"):
        main(["run", "--preset", "table1", "--duration", "100", "--memory-limit", str(limit),
              "--quiet"])


def test_config_estimate_says_what_saving_adds(capsys):
    assert main(["config", "--preset", "kaos", "--estimate"]) == 0
    out = capsys.readouterr().out
    saved = estimate(presets.get("kaos"), 1.0, save=True)
    assert (f"saved (run --out): a {format_size(saved.file_bytes)} HDF5 file built in memory "
            f"adds {format_size(saved.parts['hdf5_image'])}; peak "
            f"{format_size(saved.peak_bytes)}") in out
