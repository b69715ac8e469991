"""closedloop: numba-accelerated closed-loop MCAO simulator (not yet built).

The simulator of the paper's Section 3.4 (Table 1 preset, Figures 2-4) is the next
milestone of the roadmap. It will import bases, predictors and ``ModalLog`` from
modalinfo; modalinfo never imports closedloop.
"""

__all__: list[str] = []
