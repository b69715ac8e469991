"""How the headline numbers move with the defaults Table 1 leaves open.

:func:`sensitivity` runs the no-prediction loop (and optionally a predictor) for a base
configuration and for each variation of one default at a time, on the same seed, and
returns one row per run: SR peak and field-mean SR after closure, corrected-FoV
diameter, and the error budget's terms on axis. The science wavelength needs no new run
(the phase variance scales as ``lambda**-2``): its rows rescale the base run.

    python -m closedloop.studies.sensitivity --duration 0.3 > docs/SENSITIVITY.md
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable

import numpy as np

from closedloop import presets
from closedloop.config import SimulationConfig
from closedloop.simulation import simulate
from modalinfo.common.cli import Parser

__all__ = ["VARIATIONS", "sensitivity", "markdown"]


def _upper_altitude(h: float) -> Callable[[SimulationConfig], SimulationConfig]:
    def change(c: SimulationConfig) -> SimulationConfig:
        layers = (c.layers[0], dataclasses.replace(c.layers[1], altitude=h))
        dms = (c.dms[0], dataclasses.replace(c.dms[1], altitude=h))
        wfss = (c.wfss[0], dataclasses.replace(c.wfss[1], altitude=h))
        return c.replace(layers=layers, dms=dms, wfss=wfss)
    return change


def _wfs_fields(ground: float, upper: float):
    def change(c: SimulationConfig) -> SimulationConfig:
        return c.replace(wfss=(dataclasses.replace(c.wfss[0], field_of_view=ground),
                               dataclasses.replace(c.wfss[1], field_of_view=upper)))
    return change


def _modes(ground: int, upper: int):
    def change(c: SimulationConfig) -> SimulationConfig:
        return c.replace(dms=(dataclasses.replace(c.dms[0], n_modes=ground),
                              dataclasses.replace(c.dms[1], n_modes=upper)))
    return change


def _model_error(share: float):
    def change(c: SimulationConfig) -> SimulationConfig:
        return c.replace(loop=dataclasses.replace(c.loop, model_error=share))
    return change


#: (parameter, value label, change) applied one at a time to table1
VARIATIONS: list[tuple[str, str, Callable]] = [
    ("upper-layer altitude", "5 km", _upper_altitude(5_000.0)),
    ("upper-layer altitude", "15 km", _upper_altitude(15_000.0)),
    ("WFS fields (ground, upper)", "40\", 10\"", _wfs_fields(40.0, 10.0)),
    ("WFS fields (ground, upper)", "90\", 30\"", _wfs_fields(90.0, 30.0)),
    ("modes per DM (ground, upper)", "65, 35", _modes(65, 35)),
    ("modes per DM (ground, upper)", "189, 90", _modes(189, 90)),
    ("reconstructor model error", "0.1", _model_error(0.1)),
    ("reconstructor model error", "1.0", _model_error(1.0)),
]
_WAVELENGTHS = (500e-9, 800e-9)


def _row(parameter, value, result, scale=1.0, start: int | None = None) -> dict:
    # the SR means from ``start`` if given (a predictor's run read on its no-prediction
    # run's window, as Figures 2 and 7's tables average: round 43 PART b, R33), else from
    # the run's own window (SimulationResult's rule); the FoV diameter always on the run's
    # own window (Figure 4's and SimulationResult.summary's), also for its rescaled
    # wavelengths (the same loop, seen in another band)
    own = result.averaging_start
    start = own if start is None else int(start)
    variance = result.residual_variance[start:] * scale
    strehl = np.exp(-variance)
    peak = strehl.max(axis=1)
    row = {"parameter": parameter, "value": value,
           "strehl_peak": float(peak.mean()), "strehl_field": float(strehl.mean())}
    if scale == 1.0:
        row["fov_arcmin"] = result.corrected_fov_diameter(0.3)
    else:
        rescaled = dataclasses.replace(result, residual_variance=result.residual_variance * scale)
        row["fov_arcmin"] = rescaled.corrected_fov_diameter(0.3, start=own)
    b = result.budget
    if b is not None:
        k = int(np.argmin(np.hypot(*b.directions.T)))
        for term in ("fitting", "aliasing", "temporal", "noise", "measured"):
            row[term] = float(getattr(b, term)[k]) * scale
    return row


def sensitivity(base: SimulationConfig | None = None, *, duration: float = 0.3, seed: int = 0,
                budget_every: int | None = 5, variations=None, progress=None) -> list[dict]:
    """Run ``base`` and each variation; return one row (dict) per run.

    Parameters
    ----------
    base : SimulationConfig or None
        Default: ``presets.get("table1")``.
    duration : float
        Simulated time of each run [s].
    seed : int
        One atmosphere for all runs.
    budget_every : int or None
        Error budget every this many frames (its on-axis terms go in the rows).
    variations : list of (parameter, label, change) or None
        Default :data:`VARIATIONS`.
    progress : bool or None
        Progress bars of the runs.
    """
    base = presets.get("table1") if base is None else base
    variations = VARIATIONS if variations is None else variations
    ref = simulate(base, duration, seed=seed, progress=progress, budget_every=budget_every)
    rows = [_row("(table1 defaults)", "", ref)]
    for lam in _WAVELENGTHS:
        rows.append(_row("science wavelength", f"{lam * 1e9:.0f} nm", ref,
                         scale=(base.wavelength / lam) ** 2))
    for parameter, label, change in variations:
        result = simulate(change(base), duration, seed=seed, progress=progress,
                          budget_every=budget_every)
        rows.append(_row(parameter, label, result))
    return rows


def markdown(rows: list[dict]) -> str:
    """Return the rows as a Markdown table."""
    head = ("| parameter | value | SR peak | SR field mean | FoV d [arcmin] | fitting | "
            "aliasing | temporal | noise | measured (on axis, rad^2) |")
    lines = [head, "|" + "---|" * 10]
    for r in rows:
        terms = " | ".join(f"{r[t]:.3f}" if t in r else "" for t in
                           ("fitting", "aliasing", "temporal", "noise", "measured"))
        lines.append(f"| {r['parameter']} | {r['value']} | {r['strehl_peak']:.3f} | "
                     f"{r['strehl_field']:.3f} | {r['fov_arcmin']:.2f} | {terms} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    """Print the sensitivity table of table1 as Markdown."""
    ap = Parser(prog="python -m closedloop.studies.sensitivity")
    ap.add_argument("--duration", type=float, default=0.3)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    try:  # a bad --duration or --seed: one line, exit 2 (as the other commands)
        rows = sensitivity(duration=args.duration, seed=args.seed)
    except (ValueError, TypeError) as exc:
        sys.stderr.write(f"sensitivity: error: {str(exc).splitlines()[0]}\n")
        return 2
    sys.stdout.write(f"table1 sensitivity: seed {args.seed}, {args.duration:g} s per run, "
                     "no prediction, one default changed at a time\n\n")
    sys.stdout.write(markdown(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
