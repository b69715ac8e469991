"""Long memory-mapped logs through ``reorder``, ``fitting-error`` and ``forecast``.

References: numpy's own slicing (``coeffs[::k]``, ``coeffs[:n]``) of the array the test
wrote, for the ``--max-frames`` subsample (bit for bit); the same command on a file
holding exactly those frames (a round trip through ``modalinfo.io.save``); the
in-memory evaluation of the same values (``mmap=False``) for the chunked, mapped
``evaluate`` (bit for bit: the float64 values and the chunks are the same); the
dispatcher's contract (one line on stderr, exit 2) with ``memory_available`` set to the
command's estimate and one byte below it (the estimate recomputed here from the
documented formula: copies x frames x modes x 8 bytes).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import pytest

from modalinfo.cli import main, shared
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

N_FRAMES, N_MODES = 1200, 6


@pytest.fixture(autouse=True)
def _commands_map_every_log(monkeypatch):
    """The commands read a log below ``modalinfo.io.MAP_ABOVE`` whole (Leftovers 18):
    these tests are about the mapped path, so every log is mapped here."""
    import modalinfo.io

    monkeypatch.setattr(modalinfo.io, "MAP_ABOVE", 0)


@pytest.fixture(scope="module")
def long_npy(tmp_path_factory):
    """A float32 AR(1) log, 1200 frames x 6 Noll modes (2..7), in an NPY file."""
    rng = np.random.default_rng(3)
    e = rng.standard_normal((N_FRAMES, N_MODES))
    x = np.empty_like(e)
    x[0] = e[0]
    for t in range(1, N_FRAMES):
        x[t] = 0.9 * x[t - 1] + e[t]
    x = (x * 0.3 / np.arange(1, N_MODES + 1)).astype(np.float32)
    path = tmp_path_factory.mktemp("memmap") / "long.npy"
    np.save(path, x)
    return path, x


def _args(**kw):
    ns = argparse.Namespace(command="reorder", quiet=False, **kw)
    return ns


@pytest.mark.parametrize("limit", [1, 299, 300, 401, 1199])
def test_strided_subsample_is_numpy_slicing(long_npy, limit):
    path, x = long_npy
    log = load(path, mmap=True, rate=2000.0)
    assert isinstance(log.coeffs, np.memmap)
    part = shared.frame_subsample(log, _args(max_frames=limit))
    step = -(-N_FRAMES // limit)
    np.testing.assert_array_equal(part.coeffs, x[::step])
    assert part.coeffs.dtype == np.float32 and part.n_frames <= limit
    assert part.rate == 2000.0 / step
    assert not isinstance(part.coeffs, np.memmap)  # read into memory


def test_contiguous_subsample_is_the_first_frames(long_npy):
    path, x = long_npy
    log = load(path, mmap=True, rate=2000.0)
    part = shared.frame_subsample(log, _args(max_frames=500), contiguous=True)
    np.testing.assert_array_equal(part.coeffs, x[:500])
    assert part.rate == 2000.0


def test_short_log_is_untouched(long_npy):
    path, _ = long_npy
    log = load(path, mmap=True, rate=2000.0)
    assert shared.frame_subsample(log, _args(max_frames=N_FRAMES)) is log
    assert shared.frame_subsample(log, _args(max_frames=None)) is log


def test_reorder_max_frames_equals_the_strided_file(long_npy, tmp_path, capsys):
    path, x = long_npy
    step = 4
    save(ModalLog(x[::step], rate=2000.0 / step, modes=list(range(2, 2 + N_MODES)),
                  units="rad"), tmp_path / "strided.npz")
    common = ["--method", "mi_marginal", "--resamples", "0", "--pupil-pixels", "16",
              "--budget", "3000"]
    assert main(["reorder", str(path), "--rate", "2000", "--in-units", "rad",
                 "--max-frames", "300", *common]) == 0
    via_option = capsys.readouterr()
    assert main(["reorder", str(tmp_path / "strided.npz"), *common]) == 0
    via_file = capsys.readouterr()
    # the same ordering, bit for bit; the header says which frames (round 51 PART b, O14)
    assert via_option.out.splitlines()[1:] == via_file.out.splitlines()[1:]
    assert "pooled over every 4th frame, 300 of 1200" in via_option.out.splitlines()[0]
    assert "pooled over all frames" in via_file.out.splitlines()[0]
    assert "--max-frames 300: analysed every 4th frame (300 of 1200)" in via_option.err


def test_fitting_error_max_frames_equals_the_strided_file(long_npy, tmp_path, capsys):
    path, x = long_npy
    save(ModalLog(x[::3], rate=2000.0 / 3, modes=list(range(2, 2 + N_MODES)), units="rad"),
         tmp_path / "strided.npz")
    # (no --quiet: fitting-error's prints nothing and needs --plot since fix57-d)
    common = ["--orderings", "zernike:standard,zernike:variance", "--pupil-pixels", "16"]
    assert main(["fitting-error", str(path), "--rate", "2000", "--in-units", "rad",
                 "--max-frames", "400", *common]) == 0
    via_option = capsys.readouterr().out
    assert main(["fitting-error", str(tmp_path / "strided.npz"), *common]) == 0
    assert via_option == capsys.readouterr().out


@pytest.mark.parametrize("chunk", [7, 8192])
def test_mapped_evaluation_equals_in_memory(long_npy, chunk):
    from modalinfo.forecast import evaluate
    from modalinfo.forecast.presets import make_predictor

    path, _ = long_npy
    mapped = load(path, mmap=True, rate=2000.0)
    whole = load(path, mmap=False, rate=2000.0)
    assert isinstance(mapped.coeffs, np.memmap) and not isinstance(whole.coeffs, np.memmap)
    kw = dict(train=400, horizons=range(1, 4), chunk_frames=chunk)
    a = evaluate({"linear": make_predictor("linear")}, mapped, **kw)
    b = evaluate({"linear": make_predictor("linear")}, whole, **kw)
    for name in ("rmse", "rmse_wavefront", "dm_statistic", "one_step", "truth"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


def _refusal(capsys, *needles):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err


def _quality(frames: int, modes: int, resident: int = 0) -> int:
    """The log-quality pass's estimate (left31-estimate): it runs after the checks above,
    with ``resident`` bytes of the log in memory, and is checked on its own (the max)."""
    from modalinfo.telemetry.quality import quality_memory

    return quality_memory(frames, modes) + resident


def test_reorder_refusal_fires_at_the_boundary(long_npy, monkeypatch, capsys):
    path, _ = long_npy
    # LOG_COPIES float64 copies of the 300-frame subsample (the documented estimate)
    need = shared.LOG_COPIES * 300 * N_MODES * 8
    argv = ["reorder", str(path), "--in-units", "rad", "--max-frames", "300",
            "--method", "standard", "--resamples", "0", "--pupil-pixels", "8"]
    monkeypatch.setattr(shared, "memory_available", lambda: need - 1)
    assert main(argv) == 2
    _refusal(capsys, "--max-frames", "300 frames x 6 modes")
    # at the estimate itself it runs (the pupil grids of --pupil-pixels 8 add their own
    # check, so give them room: the refusal above is the subsample's)
    monkeypatch.setattr(shared, "memory_available",
                        lambda: max(need + 8 * 64 * 40, _quality(300, N_MODES, 300 * N_MODES * 8)))
    assert main(argv) == 0


def test_reorder_mi_refusal_counts_the_budget(long_npy, monkeypatch, capsys):
    path, _ = long_npy
    # the subsample's copies + the (modes x budget) float64 MI contributions
    need = shared.LOG_COPIES * 300 * N_MODES * 8 + 8 * N_MODES * 2000
    argv = ["reorder", str(path), "--in-units", "rad", "--max-frames", "300",
            "--method", "mi_marginal", "--budget", "2000", "--resamples", "0",
            "--pupil-pixels", "8"]
    monkeypatch.setattr(shared, "memory_available", lambda: need - 1)
    assert main(argv) == 2
    _refusal(capsys, "--budget 2000", "smaller --budget or --max-frames")
    monkeypatch.setattr(shared, "memory_available",
                        lambda: max(need + 8 * 64 * 40, _quality(300, N_MODES, 300 * N_MODES * 8)))
    assert main(argv) == 0


def test_forecast_refusal_names_train_at_the_boundary(long_npy, monkeypatch, capsys):
    from modalinfo.cli import cmd_forecast

    path, _ = long_npy
    h, n_train = 2, 500
    chunk = min(cmd_forecast.chunk_frames(h, N_MODES), N_FRAMES)
    n_origins = N_FRAMES - h - n_train + 1
    need = (cmd_forecast.TRAIN_COPIES * 8 * n_train * N_MODES  # training frames
            + 8 * 3 * h * n_origins  # per-origin losses of 3 predictors (2 baselines)
            # a chunk's forecasts (every frame) and 3 arrays over its origins: scored
            # forecasts, targets, errors (left19-est)
            + 8 * h * N_MODES * (chunk + 3 * min(chunk, n_origins)))
    argv = ["forecast", str(path), "--in-units", "rad", "--predictors", "linear",
            "--train", str(n_train), "--horizon", str(h)]
    monkeypatch.setattr(shared, "memory_available", lambda: need - 1)
    assert main(argv) == 2
    _refusal(capsys, "--train 500 (500 training frames", "smaller --horizon or --train")
    monkeypatch.setattr(shared, "memory_available",
                        lambda: max(need, _quality(N_FRAMES, N_MODES)))  # mapped: 0 resident
    assert main(argv) == 0


@pytest.mark.parametrize("tty", [False, True])
def test_subsample_progress_only_on_a_terminal(long_npy, monkeypatch, capsys, tty):
    path, x = long_npy
    monkeypatch.setattr(shared, "SUBSAMPLE_PROGRESS_FRAMES", 1)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: tty, raising=False)
    log = load(path, mmap=True, rate=2000.0)
    part = shared.frame_subsample(log, _args(max_frames=100))
    np.testing.assert_array_equal(part.coeffs, x[::12])
    err = capsys.readouterr().err
    assert ("read" in err and "frame" in err) is tty, err


def test_select_max_frames_equals_the_first_frames_file(long_npy, tmp_path, capsys):
    path, x = long_npy
    save(ModalLog(x[:600], rate=2000.0, modes=list(range(2, 2 + N_MODES)), units="rad"),
         tmp_path / "first.npz")
    common = ["--target", "Z3", "--max-lag", "3", "--surrogates", "19", "--no-intervals"]
    assert main(["select", str(path), "--rate", "2000", "--in-units", "rad",
                 "--max-frames", "600", *common]) == 0
    via_option = capsys.readouterr()
    assert main(["select", str(tmp_path / "first.npz"), *common]) == 0
    assert via_option.out == capsys.readouterr().out
    assert "--max-frames 600: analysed frames 0..599 of 1200" in via_option.err


def _forecast_need(n_modes: int, h: int = 2, n_train: int = 500) -> int:
    """The in-memory forecast estimate: LOG_COPIES float64 copies of the selected
    columns, the per-origin losses of 3 predictors, a chunk's forecasts (every frame)
    and its origins' scored forecasts, targets and errors."""
    from modalinfo.cli import cmd_forecast

    chunk = min(cmd_forecast.chunk_frames(h, n_modes), N_FRAMES)
    n_origins = N_FRAMES - h - n_train + 1
    return (shared.LOG_COPIES * 8 * N_FRAMES * n_modes + 8 * 3 * h * n_origins
            + 8 * h * n_modes * (chunk + 3 * min(chunk, n_origins)))


def test_forecast_modes_of_a_mapped_log_equal_the_selected_file(long_npy, tmp_path, capsys,
                                                                monkeypatch):
    import modalinfo.telemetry.scan as scan

    path, x = long_npy
    cols = [0, 2, 5]  # Z2, Z4, Z7: not a consecutive range, so gathered into memory
    save(ModalLog(x[:, cols], rate=2000.0, modes=[2, 4, 7], units="rad"),
         tmp_path / "selected.npz")
    common = ["--predictors", "linear", "--train", "500", "--horizon", "2"]
    monkeypatch.setattr(scan, "SCAN_ELEMENTS", 7 * N_MODES)  # 7-frame blocks: 172 of them
    assert main(["forecast", str(path), "--rate", "2000", "--in-units", "rad",
                 "--modes", "2,4,7", *common]) == 0
    via_option = capsys.readouterr().out
    assert main(["forecast", str(tmp_path / "selected.npz"), *common]) == 0
    via_file = capsys.readouterr().out
    assert via_option.split("\n", 1)[1] == via_file.split("\n", 1)[1]  # past the file name
    assert "1200 frames x 3 modes" in via_option


def test_forecast_modes_refused_before_the_columns_are_read(long_npy, monkeypatch, capsys):
    path, _ = long_npy
    taken: list[int] = []
    take = ModalLog._take_modes

    def spy(self, columns):
        taken.append(self.n_frames)
        return take(self, columns)

    monkeypatch.setattr(ModalLog, "_take_modes", spy)
    need = _forecast_need(3)
    argv = ["forecast", str(path), "--rate", "2000", "--in-units", "rad", "--modes", "2,4,7",
            "--predictors", "linear", "--train", "500", "--horizon", "2"]
    monkeypatch.setattr(shared, "memory_available", lambda: need - 1)
    assert main(argv) == 2
    _refusal(capsys, "--modes 2,4,7 (3 of the 6 columns", "gathered into memory")
    assert max(taken) == 1  # only the one-frame head was taken: no column was copied
    monkeypatch.setattr(shared, "memory_available",
                        lambda: max(need, _quality(N_FRAMES, 3, N_FRAMES * 3 * 8)))
    assert main(argv) == 0


def test_forecast_consecutive_modes_stay_mapped(long_npy, monkeypatch, capsys):
    from modalinfo.cli import cmd_forecast

    path, _ = long_npy
    seen = []
    check = cmd_forecast._check_resources

    def spy(args, log, *rest, **kw):
        seen.append(cmd_forecast._mapped(log))
        return check(args, log, *rest, **kw)

    monkeypatch.setattr(cmd_forecast, "_check_resources", spy)
    assert main(["forecast", str(path), "--rate", "2000", "--in-units", "rad", "--modes",
                 "3-5", "--predictors", "linear", "--train", "500", "--horizon", "2"]) == 0
    assert seen == [True]


@pytest.fixture(scope="module")
def z1501_npz(tmp_path_factory):
    """A 400-frame log of Noll modes Z2, Z3 and Z1501 in an NPZ file."""
    rng = np.random.default_rng(8)
    path = tmp_path_factory.mktemp("z1501") / "z1501.npz"
    save(ModalLog(rng.standard_normal((400, 3)), rate=1e3, modes=[2, 3, 1501], units="rad"),
         path)
    return path


@pytest.mark.parametrize("command", [
    ["reorder", "--method", "standard", "--resamples", "0"],
    ["fitting-error", "--orderings", "zernike:standard"],
])
def test_pupil_sampling_refused_before_any_frame_is_read(z1501_npz, monkeypatch, capsys,
                                                         command):
    # Noll (1976): radial order n holds j in (n (n + 1) / 2, (n + 1)(n + 2) / 2], so
    # Z1501 (1485 < 1501 <= 1540) is order 54, which needs 2 x 54 = 108 pixels across
    from modalinfo.cli import cmd_reorder

    def never(*_a, **_k):
        raise AssertionError("frame_subsample called: the frames were read before the refusal")

    monkeypatch.setattr(cmd_reorder, "frame_subsample", never)
    monkeypatch.setattr(shared, "frame_subsample", never)
    argv = [command[0], str(z1501_npz), *command[1:], "--max-frames", "100"]
    assert main([*argv, "--pupil-pixels", "107"]) == 2
    _refusal(capsys, "--pupil-pixels must be >= 108 to sample Z1501 (radial order 54")
    assert main([*argv]) == 2  # the default 64
    _refusal(capsys, "got 64")
    with pytest.raises(AssertionError, match="frame_subsample called"):
        main([*argv, "--pupil-pixels", "108"])  # passes the rule, so reads the frames
