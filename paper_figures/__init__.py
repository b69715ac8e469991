"""Scripts that regenerate every figure of the paper, one module per figure.

Each figure module exposes ``make(out_dir, log_path) -> str`` returning a Markdown
section for the report, and runs stand-alone (``python -m paper_figures.fig1_fitting_error``).
``python -m paper_figures`` makes them all and writes ``report.md`` beside them.
"""

__all__ = ["FIGURES"]

#: (module name, paper figure, short title) in the order the report presents them.
FIGURES = [
    ("fig1_fitting_error", "Figure 1", "Fitting error vs number of modes (MI reordering)"),
    ("fig5_forecast", "Figure 5", "Forecasts of a modal coefficient (linear, ARMA, NN)"),
]
