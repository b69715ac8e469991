r"""Stop 57, fix51-c item 4: Figure 5's report shows a log's mode label as typed.

``fig5_forecast.report`` put the first mode's label raw into the Markdown
(``**{label}**``, "for {label};", "on {label} alone"): a ``*`` or ``_`` opened an
emphasis, a ``<b>`` became an element in report.html, a backtick opened code, a ``|``
and a newline were the text's. The label is a log's own (an NPZ's ``labels``, a CSV
header), so any text.

References, outside the package: two Markdown renderers (Python-Markdown, which
report.html is made with, and markdown-it-py's CommonMark, GitHub's reading of
report.md) and the report of the plain label ``Z2`` as the expected structure: every
other label must give the same rendered elements (tags other than ``code``) and, as
text, the plain report's with ``Z2`` replaced by the label (its
``modalinfo.common.files.shown_name`` form for a newline). Figure 5 is the hand-made
result of test_mutation_gaps_fig5_forecast.py with the label changed.
"""

from __future__ import annotations

import dataclasses

import pytest

from paper_figures import fig5_forecast as fig5

from .test_mutation_gaps_fig5_forecast import _figure
from .test_report_names_fix50b import _renderers, _tree

LABELS = ["*Z2*", "_tip_", "<b>Z2</b>", "Z`2", "a|b", "**x**", "Z2 & <script>", "a\nb"]


@pytest.mark.parametrize("label", LABELS)
@pytest.mark.parametrize("renderer", ["python-markdown", "gfm"])
def test_label_renders_as_typed(label, renderer):
    render = _renderers()[renderer]
    plain = _tree(render(fig5.report(_figure())))
    text = _tree(render(fig5.report(dataclasses.replace(_figure(), label=label))))
    assert text.tags == plain.tags, (label, text.tags)
    shown = label.replace("\n", "\\n")  # shown_name's one printable line
    expected = plain.text.replace("Z2", "\0").replace("\0", shown)
    assert text.text == expected
