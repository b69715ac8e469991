"""Command-line messages of fix55-c (adversarial round 54 PART b, "Left"), issue 27.

References: the file system (an existing folder given where a file is written), the
README's promise that an HDF5 file holding modalinfo logs in groups is read with
``--dataset GROUP``, and, for the log read out of a closedloop result, the result's own
reader ``closedloop.SimulationResult.load`` and the raw datasets read by h5py.
"""

import h5py
import numpy as np
import pytest

from closedloop import SimulationResult, simulate
from closedloop.cli import main as closedloop_main
from modalinfo.cli import main
from modalinfo.io import LogFormatError, load

from ..closedloop.conftest import tiny_actuator_config  # the closedloop tests' small loop


@pytest.fixture(scope="module")
def log_file(tmp_path_factory):
    out = tmp_path_factory.mktemp("log") / "s.npz"
    assert main(["synth", str(out), "--frames", "300", "--seed", "3", "--quiet"]) == 0
    return out


@pytest.mark.parametrize(("prog", "argv", "flag", "suffix"), [
    (main, ["reorder", "{log}", "--method", "variance", "--resamples", "0", "--out", "{dir}"],
     "--out", ".json"),
    (main, ["convert", "{log}", "{dir}"], "OUT", ".npz"),
    (main, ["convert", "{log}", "{dir}", "--to-fmt", "csv"], "OUT", ".csv"),
    (main, ["synth", "{dir}", "--frames", "100"], "OUT", ".npz"),
    (main, ["fitting-error", "{log}", "--orderings", "zernike:standard", "--plot", "{dir}"],
     "--plot", ".png"),
    (closedloop_main, ["run", "--preset", "table1", "--duration", "0.01", "--out", "{dir}"],
     "--out", ".h5"),
    (closedloop_main, ["config", "--preset", "table1", "--out", "{dir}"], "--out", ".toml"),
])
def test_a_folder_given_as_an_output_file_is_named(tmp_path, capsys, log_file, prog, argv,
                                                   flag, suffix):
    folder = tmp_path / "fc1"
    folder.mkdir()
    args = [a.format(log=log_file, dir=folder) for a in argv]
    assert prog(args) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1, err
    assert f"{flag} '{folder}' is a folder" in err, err
    assert "unsupported extension" not in err and "cannot tell" not in err
    assert f"'{folder / ('NAME' + suffix)}'" in err, err  # an example of what it wants
    assert list(folder.iterdir()) == []


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    return simulate(tiny_actuator_config(), 0.005, seed=0).save(
        tmp_path_factory.mktemp("r") / "r.h5")


@pytest.mark.parametrize("name", ["logs/dm0.pol", "logs/dm0.pol/coefficients", "/logs/dm0.pol"])
def test_a_result_log_named_by_dataset_is_read(result_file, name):
    log = load(result_file, dataset=name)
    ref = SimulationResult.load(result_file).logs["dm0.pol"]
    with h5py.File(result_file, "r") as f:
        raw = f["logs/dm0.pol/coefficients"][()]
    np.testing.assert_array_equal(log.coeffs, raw)
    np.testing.assert_array_equal(log.coeffs, ref.coeffs)
    assert log.rate == ref.rate and log.units == ref.units == "rad"
    assert log.wavelength == ref.wavelength and list(log.modes) == list(ref.modes)
    assert log.metadata["loop"] == "closed" and log.metadata["coefficient_quantity"] == "pol"


def test_info_reads_the_result_log(result_file, capsys):
    assert main(["info", str(result_file), "--dataset", "logs/dm0.pol"]) == 0
    out = capsys.readouterr().out
    assert "pseudo-open-loop coefficients" in out


@pytest.mark.parametrize(("name", "words"), [
    ("logs/dm0.residual", "closedloop export"),
    ("logs/dm0.commands", "SimulationResult.load"),
])
def test_a_closed_loops_residual_and_commands_are_refused_with_the_way(result_file, capsys,
                                                                      name, words, tmp_path):
    # a result saved before fix56-c, which stores the closure transient (the dataset
    # transient_frames; with it they are read: tests/closedloop/test_transient_servo_fix56c)
    old = tmp_path / "old.h5"
    old.write_bytes(result_file.read_bytes())
    with h5py.File(old, "a") as f:
        del f["transient_frames"]
    assert main(["info", str(old), "--dataset", name]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "closure transient" in err and words in err, err
    assert "--dataset logs/dm0.pol" in err


def test_without_a_dataset_the_logs_are_listed(result_file):
    with pytest.raises(LogFormatError, match="is a closedloop result, not a log") as err:
        load(result_file)
    assert "--dataset logs/dm0.pol" in str(err.value) and "logs/dm0.residual" in str(err.value)
    with pytest.raises(LogFormatError, match="'times' is not one of its logs"):
        load(result_file, dataset="times")
