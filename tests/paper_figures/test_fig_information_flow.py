"""Figure 8 (information flow): the figure module on telemetry with planted transfer.

Reference: a planted VAR network written here (independent AR(1) drivers feeding
targets at known lags, a second "sensor" log whose mode copies the first log's mode
5 frames later), so the links the report lists, their lags in frames and in ms (at the
log's 500 Hz) and the cross-sensor count are known in advance; the report's table and
the comparison row are re-read from the JSON the figure wrote, so they are shown to
come from the computed map. The full path (shipped logs, a table1-wind run) runs in
``test_main_quick.py``.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog
from paper_figures import fig_information_flow as fig8


def _planted(n: int, seed: int) -> tuple[ModalLog, ModalLog]:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 50, 4))
    x = np.zeros_like(e)
    for t in range(3, n + 50):
        x[t, 0] = 0.3 * x[t - 1, 0] + e[t, 0]
        x[t, 2] = 0.3 * x[t - 1, 2] + e[t, 2]
        x[t, 1] = 0.5 * x[t - 1, 1] + 0.5 * x[t - 3, 0] + e[t, 1]   # Z2 -> Z3 at 3 frames
        x[t, 3] = 0.3 * x[t - 1, 3] + e[t, 3]
    x = x[50:]
    other = np.roll(x[:, 2], 5)[:, None] + 0.5 * rng.standard_normal((n, 1))  # Z4 -> extra:Z2, 5
    return ModalLog(x, rate=500.0), ModalLog(other, rate=500.0)


@pytest.fixture(scope="module")
def result():
    log, other = _planted(3000, 0)
    return fig8.compute(seed=0, datasets=[("planted", "planted network", log, other, None,
                                           None)])


def test_links_are_the_planted_ones(result):
    (fs,) = result.sets
    links = {(s, t): lag for s, t, lag, _, _ in fs.flow.links()}
    assert links == {("Z2", "Z3"): 3, ("Z4", "extra:Z2"): 5}
    assert fs.flow.lags.tolist() == list(fig8.LAGS)
    assert fs.flow.n_surrogates == fig8.N_SURROGATES and fs.flow.history == fig8.HISTORY


def test_report_and_row_come_from_the_written_numbers(result, tmp_path):
    paths = fig8.plot(result, tmp_path)
    assert [p.name for p in paths] == [fig8.FIGURE_NAME, fig8.PDF_NAME, fig8.JSON_NAME]
    assert (tmp_path / fig8.FIGURE_NAME).stat().st_size > 10_000
    data = json.loads((tmp_path / fig8.JSON_NAME).read_text())["planted"]
    te, p = np.array(data["te"]), np.array(data["pvalue"])
    labels, lags = data["labels"], data["lags"]
    # recompute the links from the JSON: best lag of each pair, significant at alpha
    rows = []
    for j in range(len(labels)):
        for i in range(len(labels)):
            if i != j:
                a = int(np.argmax(te[j, i]))
                if p[j, i, a] <= data["alpha"]:
                    rows.append((te[j, i, a], labels[j], labels[i], lags[a], p[j, i, a]))
    rows.sort(reverse=True)
    text = fig8.report(result)
    assert "## Figure 8: Information flow between modes (extension, not in the paper)" in text
    for v, s, t, lag, pv in rows:
        ms = lag * 1e3 / data["rate"]
        assert f"| {s} | {t} | {lag} | {ms:g} | {v:.4f} | {pv:.3f} |" in text
    (row,) = fig8.table_rows(result)
    v, s, t, lag, _ = rows[0]
    assert row[1] == "not in the paper"
    assert row[2] == (f"{len(rows)} of 20 pairs; strongest {s} -> {t} at "
                      f"{lag * 1e3 / data['rate']:g} ms ({v:.4f} nats)")


def test_json_undefined_cells_are_null(result, tmp_path):
    # audit 10, feedback, row pf-fig8-json-sentinel: a mode to itself was written as TE -1
    # nats and p-value -1, numbers a reader takes for values
    fig8.plot(result, tmp_path)
    data = json.loads((tmp_path / fig8.JSON_NAME).read_text())["planted"]
    (fs,) = result.sets
    for key, values in (("te", fs.flow.te), ("pvalue", fs.flow.pvalue)):
        written = data[key]
        for j, i, lag in np.ndindex(values.shape):
            v = written[j][i][lag]
            assert (v is None) if np.isnan(values[j, i, lag]) else v == values[j, i, lag]
        assert all(written[k][k][0] is None for k in range(len(written)))


def test_stand_alone_command_refuses_to_replace(tmp_path, capsys):
    (tmp_path / fig8.FIGURE_NAME).write_bytes(b"x")
    assert fig8.main(["--out", str(tmp_path)]) == 2
    assert "exists; pass --overwrite" in capsys.readouterr().err
    assert (tmp_path / fig8.FIGURE_NAME).read_bytes() == b"x"
