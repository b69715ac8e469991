"""Scripts that regenerate every figure of the paper, one module per figure.

Figures 1 and 5 analyse a modal log: ``make(out_dir, log_path, *, suffix="") -> str``,
with ``compute(log, *, source=...)`` (a frozen result of numbers), ``plot(result,
out_dir, *, suffix="")``, ``report(result, *, suffix="")``, ``table_rows(result)``
(paper vs ours) and ``output_names(suffix)``. Figures 2-4 (``NEEDS_RUNS = True``) draw
the closed-loop runs that they share (:mod:`paper_figures.closedloop_runs`, computed
once): ``make(out_dir, runs) -> str``; each of them has a ``compute`` (numbers),
``plot`` and ``report`` step. Figure 6 (``NEEDS_LOG = False``, not in the paper: the
study its conclusion proposes) runs its own loops: ``compute(quick=, seed=)``; so does
Figure 8 (an extension: the transfer-entropy map of the shipped logs and a table1-wind
run). Figure 7 (an extension, ``NEEDS_RUNS = True``: Figures 2-4 again with the solar
correlating sensor) receives the table1 runs and runs ``table1-solar`` beside them. Every
module has ``table_rows(result)``: ``(quantity, paper, ours, why they differ)`` rows of
the report's comparison table. ``python -m paper_figures`` makes them all and writes
``report.md`` and ``report.html`` beside them.
"""

import contextlib
import contextvars
import sys
from collections.abc import Iterator
from pathlib import Path

__all__ = ["FIGURES", "program", "run_as", "tell"]

#: (module name, paper figure, short title) in the order the report presents them.
FIGURES = [
    ("fig1_fitting_error", "Figure 1", "Fitting error vs number of modes (MI reordering)"),
    ("fig2_sr_peak", "Figure 2", "SR peak vs time (closed-loop MCAO, every predictor)"),
    ("fig3_sr_spectrum", "Figure 3", "Power spectra of the SR-peak oscillations"),
    ("fig4_sr_maps", "Figure 4", "Time-averaged SR maps and the corrected field of view"),
    ("fig5_forecast", "Figure 5", "Forecasts of a modal coefficient (linear, ARMA, NN)"),
    ("fig6_compression", "Figure 6",
     "Compression x prediction: controlled modes of each ordering, with latency"),
    ("fig7_solar", "Figure 7",
     "Solar correlating sensing: Figures 2-4 on table1-solar (extension, not in the paper)"),
    ("fig_information_flow", "Figure 8",
     "Information flow between modes (transfer entropy; extension, not in the paper)"),
]


#: the program as typed (:func:`program`), set by :func:`run_as`
_PROGRAM: contextvars.ContextVar[str | None] = contextvars.ContextVar(
    "paper_figures_program", default=None)


def program() -> str:
    """Return the program as typed, which starts every line paper_figures writes on stderr.

    Set by run_as (``python -m paper_figures`` and each stand-alone
    ``python -m paper_figures.figN_...``); outside, the console script ``paper-figures``
    when typed so, else ``python -m paper_figures``. Its errors named the program typed
    while its notes and warnings said "paper_figures:" (fixes 47-b; fixes 45-c, c08).
    """
    prog = _PROGRAM.get()
    if prog is not None:
        return prog
    return ("paper-figures" if Path(sys.argv[0] or "").name == "paper-figures"
            else "python -m paper_figures")


@contextlib.contextmanager
def run_as(prog: str) -> Iterator[None]:
    """Within the block, program is ``prog`` (this context only)."""
    token = _PROGRAM.set(prog)
    try:
        yield
    finally:
        _PROGRAM.reset(token)


def tell(kind: str | None, text: str) -> None:
    """Write ``<program>: <kind>: <text>`` (no kind: ``<program>: <text>``) on stderr, one line.

    The one form of paper_figures' notes, warnings and ends (program); a stderr
    that refuses the line keeps the exit status (``modalinfo.common.cli.say``).
    """
    from modalinfo.common.cli import say

    say(f"{program()}: {kind + ': ' if kind else ''}{text}\n")
