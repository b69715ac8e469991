"""The stand-alone figure scripts take the output lock ``python -m paper_figures`` takes.

Issue 27, left13-cli item 2: ``python -m paper_figures`` locks its ``--out`` folder as
``modalinfo batch`` does, but ``python -m paper_figures.figN_...`` took no lock (and Figures
6-8 wrote straight into the folder): two runs into one folder replaced each other's files
unasked. Reference, outside the scripts: the folder's lock held by another run (taken here
with ``paper_figures._common.locked_output``, the lock the whole-paper command holds), and
the folder's listing before and after. The figures' computations are replaced by a stub
that writes the named files, so only the command line's handling is under test.
"""

from __future__ import annotations

import pytest

from paper_figures import _common, fig1_fitting_error, fig6_compression, fig7_solar
from paper_figures import fig_information_flow as fig8


def _stub(module, names, calls):
    def make(stage, *args, **kwargs):
        calls.append(module.__name__)
        for name in names:
            (stage / name).write_text("drawn")
        return "report"
    return make


def _fig1_names():
    return fig1_fitting_error.output_names("")


CASES = [
    ("fig1", fig1_fitting_error, _fig1_names, []),
    ("fig6", fig6_compression,
     lambda: [fig6_compression.FIGURE_NAME, fig6_compression.PDF_NAME], ["--quick"]),
    ("fig8", fig8, lambda: [fig8.FIGURE_NAME, fig8.PDF_NAME, fig8.JSON_NAME], ["--quick"]),
    ("fig7", fig7_solar,
     lambda: [fig7_solar.FIGURE_NAME, fig7_solar.PDF_NAME, fig7_solar.JSON_NAME], ["--quick"]),
]


@pytest.mark.parametrize(("short", "module", "names", "extra"), CASES,
                         ids=[c[0] for c in CASES])
def test_a_held_folder_is_refused_and_left_as_it_was(tmp_path, monkeypatch, capsys, short,
                                                      module, names, extra):
    calls: list = []
    monkeypatch.setattr(module, "make", _stub(module, names(), calls))
    if module is fig7_solar:  # its shared closed-loop runs, not under test
        from paper_figures import closedloop_runs
        monkeypatch.setattr(closedloop_runs, "compute", lambda **kw: None)
    out = tmp_path / "out"
    out.mkdir()
    (out / "other.txt").write_text("another run's file")
    with _common.locked_output(out):
        code = module.main(["--out", str(out), *extra])
        err = capsys.readouterr().err.strip()
        assert code == 2 and calls == []
        assert len(err.splitlines()) == 1 and err.startswith(f"python -m {module.__name__}: error:")
        assert "in use" in err and ".lock" in err
        assert sorted(p.name for p in out.iterdir()) == [".lock", "other.txt"]
    # free again: the run writes its files, and a second refuses to replace them unasked
    assert module.main(["--out", str(out), *extra]) == 0
    assert sorted(p.name for p in out.iterdir()) == sorted(["other.txt", *names()])
    assert module.main(["--out", str(out), *extra]) == 2
    assert "exists; pass --overwrite" in capsys.readouterr().err
    assert len(calls) == 1
