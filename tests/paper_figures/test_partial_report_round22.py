"""Round 22 PART b: the report of a partial run names the figures it did not make.

Reference: the list of the paper's figures (``paper_figures.FIGURES``, eight figures) minus
the one the run made: the report must name every other one as not made.
"""
from __future__ import annotations

import types
from argparse import Namespace

from modalinfo.common.provenance import provenance
from paper_figures import FIGURES
from paper_figures.__main__ import _make


def test_report_after_one_figure_names_the_rest(tmp_path):
    fake = types.SimpleNamespace(
        NEEDS_LOG=False,
        compute=lambda quick, seed: 1.0,
        plot=lambda result, stage: None,
        report=lambda result: "## Figure 8: stub\n",
        table_rows=lambda result: [],
    )
    name, label, title = FIGURES[-1]
    _make(Namespace(quick=True, seed=0, duration=None), [(fake, label, title)], {}, [],
          False, tmp_path, provenance(None, seed=0))
    head = (tmp_path / "report.md").read_text(encoding="utf-8").split("\n## ")[0]
    others = [lab for _, lab, _ in FIGURES if lab != label]
    assert len(others) == 7
    assert "not made here" in head
    for lab in others:
        assert lab in head
