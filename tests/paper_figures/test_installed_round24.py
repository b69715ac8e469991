"""Round 24 PART b: paper_figures installed from a wheel (no data/) says so.

Reference: the wheel itself (outside the code): ``pip wheel . --no-deps`` packs
``modalinfo*``, ``closedloop*`` and ``paper_figures*`` only (pyproject
``[tool.setuptools.packages.find]``), so an installed ``python -m paper_figures`` finds
no ``data/``. Before, it said "log file '.../site-packages/data/kaos_like_closed_loop.npz'
does not exist", naming a path the user never gave. Simulated here by pointing the
shipped logs at a folder that does not exist.
"""
from __future__ import annotations

import paper_figures.__main__ as pf_main


def test_missing_shipped_data_is_named_with_the_way_out(tmp_path, monkeypatch, capsys):
    gone = tmp_path / "site-packages" / "data"
    monkeypatch.setattr(pf_main, "SHIPPED_LOGS", tuple(
        (gone / path.name, *rest) for path, *rest in pf_main.SHIPPED_LOGS))
    code = pf_main.main(["--only", "1", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    assert "not installed with the package" in err and "--log" in err
    assert not (tmp_path / "out").exists()


def test_figure_8_without_shipped_data_is_refused_before_work(tmp_path, monkeypatch, capsys):
    """Figure 8 reads the shipped logs whatever --log says: before, exit 1 after start-up
    with "FileNotFoundError: no such file: '.../site-packages/data/...'"."""
    import paper_figures.fig_information_flow as fig8

    gone = tmp_path / "site-packages" / "data"
    monkeypatch.setattr(fig8, "SHIPPED", tuple(
        (key, gone / path.name, *rest) for key, path, *rest in fig8.SHIPPED))
    code = pf_main.main(["--only", "8", "--quick", "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    assert "not installed with the package" in err and "--only" in err
    assert not (tmp_path / "out").exists()
