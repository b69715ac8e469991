"""The two shipped logs side by side: spectral (Conan spectra) vs simulated (closedloop).

``data/kaos_like_closed_loop.npz`` is drawn from temporal spectra (Conan, Rousset &
Madec 1995 asymptotes per radial order, an ideal modal integrator, white noise equal for
every mode); ``data/kaos_closedloop.npz`` comes out of the ``closedloop`` simulator's
``kaos`` preset (frozen-flow layers moving along their wind, a Shack-Hartmann whose
slopes also see the turbulence beyond Z28, noise propagated through the reconstructor).
:func:`compute` measures, on both, the statistics where the two models differ, so that
the report can say how and why the figures change between them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalinfo.bases import noll_to_zernike

__all__ = ["LogStatistics", "LogsCompared", "statistics", "compute", "report"]


@dataclass(frozen=True)
class LogStatistics:
    """Statistics of one log where the two models differ.

    Attributes
    ----------
    name : str
    total : float
        Sum over modes of the coefficient variance [waves^2].
    tilt_ratio : float
        Var(Z2) / Var(Z3): 1 for spectra without a wind direction.
    high_order_share : float
        Share of the variance in radial orders >= 5 (Z16 and above).
    lagged_cross : float
        Largest |correlation| between mode i at frame t and mode j != i at frame t + 1
        (frozen flow moves one mode's pattern into another's).
    lag1 : float
        Mean over modes of the lag-1 autocorrelation of the coefficients.
    """

    name: str
    total: float
    tilt_ratio: float
    high_order_share: float
    lagged_cross: float
    lag1: float


@dataclass(frozen=True)
class LogsCompared:
    """The spectral and the simulated log's statistics."""

    spectral: LogStatistics
    simulated: LogStatistics


def statistics(log, name: str) -> LogStatistics:
    """Measure :class:`LogStatistics` on a Noll-indexed ModalLog."""
    waves = log.to_units("waves") if log.units != "waves" else log
    x = np.asarray(waves.coeffs, dtype=np.float64)
    x = x - x.mean(axis=0)
    var = x.var(axis=0)
    modes = [int(m) for m in log.modes]
    radial, _ = noll_to_zernike(np.array(modes))
    std = x / np.sqrt(var)
    lagged = std[:-1].T @ std[1:] / (x.shape[0] - 1)
    off = np.abs(lagged - np.diag(np.diag(lagged)))
    i2, i3 = modes.index(2), modes.index(3)
    return LogStatistics(
        name=name, total=float(var.sum()), tilt_ratio=float(var[i2] / var[i3]),
        high_order_share=float(var[radial >= 5].sum() / var.sum()),
        lagged_cross=float(off.max()), lag1=float(np.mean(np.diag(lagged))))


def compute(spectral_log, simulated_log) -> LogsCompared:
    """Statistics of both logs."""
    return LogsCompared(spectral=statistics(spectral_log, "spectral"),
                        simulated=statistics(simulated_log, "simulated"))


def report(cmp: LogsCompared, fig1: dict | None = None, fig5: dict | None = None) -> str:
    """Return the report's section on how the figures differ between the two logs.

    ``fig1`` / ``fig5``: log name ("spectral", "simulated") -> the figure's result
    object, when those figures were made.
    """
    a, b = cmp.spectral, cmp.simulated
    rows = [
        "| statistic | spectral log | simulated log |", "|---|---|---|",
        f"| total variance [waves^2] | {a.total:.3g} | {b.total:.3g} |",
        f"| Var(Z2) / Var(Z3) | {a.tilt_ratio:.2f} | {b.tilt_ratio:.2f} |",
        f"| variance share of radial orders >= 5 | {a.high_order_share:.1%} | "
        f"{b.high_order_share:.1%} |",
        f"| largest lag-1 cross-correlation between modes | {a.lagged_cross:.2f} | "
        f"{b.lagged_cross:.2f} |",
        f"| mean lag-1 autocorrelation | {a.lag1:.2f} | {b.lag1:.2f} |",
    ]
    extra = []
    if fig1 and {"spectral", "simulated"} <= set(fig1):
        f_a, f_b = fig1["spectral"], fig1["simulated"]
        n_a = f_a.typical.modes_at_target
        n_b = f_b.typical.modes_at_target
        extra.append(
            "Figure 1 on the typical frame, modes to reach the calibrated target (standard "
            "Zernike / MI K-L / MI Zernike): spectral "
            + " / ".join(str(n_a.get(k, "-")) for k in ("zernike:standard",
                                                       "kl-theory:mi_greedy",
                                                       "zernike:mi_greedy"))
            + ", simulated "
            + " / ".join(str(n_b.get(k, "-")) for k in ("zernike:standard",
                                                       "kl-theory:mi_greedy",
                                                       "zernike:mi_greedy"))
            + ".")
    if fig5 and {"spectral", "simulated"} <= set(fig5):
        g_a, g_b = fig5["spectral"], fig5["simulated"]
        extra.append(
            f"Figure 5, whole-wavefront gain over persistence at one frame: ARMA(2,3) "
            f"x{g_a.gain('ARMA(2,3)'):.2f} (spectral) vs x{g_b.gain('ARMA(2,3)'):.2f} "
            f"(simulated); best predictor {g_a.best_one_step} vs {g_b.best_one_step}.")
    aniso = (f"x and y tilt differ more (Var(Z2) / Var(Z3) {b.tilt_ratio:.2f} against "
             f"{a.tilt_ratio:.2f})" if abs(b.tilt_ratio - 1) > abs(a.tilt_ratio - 1)
             else "the tilt ratio does not separate them here")
    coupling = ("stronger" if b.lagged_cross > a.lagged_cross else "not stronger")
    high = (f"the simulated log's high orders hold more of its variance "
            f"({b.high_order_share:.1%} against {a.high_order_share:.1%}), as aliasing "
            "from the turbulence beyond Z28 adds to them"
            if b.high_order_share > a.high_order_share else
            f"the spectral log's high orders hold more of its variance "
            f"({a.high_order_share:.1%} against {b.high_order_share:.1%}): its white noise, "
            "equal in every mode, weighs most on the high orders whose turbulence the loop "
            "leaves small, more than aliasing from beyond Z28 lifts the simulated ones")
    smooth = ("smoother" if b.lag1 > a.lag1 else "rougher")
    return f"""## The spectral and the simulated KAOS-like logs

Figures 1 and 5 run on two shipped logs of the same system (0.7 m, Z2-Z28, 2 kHz,
r0 = 7 cm, 130 Hz integrator): `data/kaos_like_closed_loop.npz`, drawn from Conan
spectra (`modalinfo.telemetry.synthetic.kaos_like`), and `data/kaos_closedloop.npz`,
the WFS residual of the `closedloop` `kaos` preset (frozen flow, Shack-Hartmann,
noise through the reconstructor; its provenance is in its metadata).

{chr(10).join(rows)}

How and why they differ: frozen flow moves each layer's pattern along its wind, so
one mode's pattern flows into others from one frame to the next; the lagged coupling
between modes is {coupling} in the simulated log ({b.lagged_cross:.2f} against
{a.lagged_cross:.2f} for spectra that are coupled only at zero lag), and {aniso} (Conan
spectra carry no wind direction). The Shack-Hartmann sees the turbulence beyond Z28,
which aliases into the measured modes, while the spectral model adds white noise of
equal variance to every mode: {high}. The simulated residual is {smooth} in time (mean
lag-1 autocorrelation {b.lag1:.2f} against {a.lag1:.2f}). {" ".join(extra)}
"""
