"""Figure 1 of the paper: wavefront fitting error vs number of modes, MI reordering.

Paper (Stangalini et al., Section 2.1, Fig. 1): for "a typical wavefront
representation" of the VTT/KAOS closed-loop log, the fitting error
dPhi(n) = |Phi(n) - Phi(27)|^2 with the standard Zernike order (dotted blue), the
MI-ordered K-L basis (dashed green) and the MI-ordered Zernike basis (solid red);
0.4 waves^2 is reached with 20, 15 and 7 modes.

Here: the same three curves plus the data-PCA (empirical K-L) order, the mean-square
floor, and the per-frame a_k^2 order of the Zernikes (the exact per-frame optimum of
an orthonormal basis, by Parseval), for (a) the typical frame of the log (the frame of
median total variance; per-frame MI orderings on its pupil pixels; the same count on
15 frames spread through the log), (b) the average
over frames (pooled MI orderings) and (c) the same turbulence in open loop (synthetic
``kaos_like(closed_loop=False)``), where K-L modes are expected to win.

Usage::

    python -m paper_figures.fig1_fitting_error [--log LOG] [--out DIR]
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

from paper_figures._common import figure_main, load_log

SPECS = [("zernike", "standard"), ("kl-theory", "mi_greedy"), ("zernike", "mi_greedy"),
         ("kl-data", "pca"), ("zernike", "variance")]
PAPER = {"zernike:standard": 20, "kl-theory:mi_greedy": 15, "zernike:mi_greedy": 7}
PAPER_TARGET = 0.4  # waves^2
FIGURE_NAME = "fig1_fitting_error.png"
POOLED_BUDGET = 100_000
OPEN_LOOP_FRAMES = 2000
N_FRAMES = 15
LABELS = {
    "zernike:standard": "Zernike, standard order",
    "kl-theory:mi_greedy": "K-L (theory), MI order",
    "zernike:mi_greedy": "Zernike, MI order",
    "kl-data:pca": "data K-L (PCA) order",
    "zernike:variance": "Zernike, a_k^2 order",
}



def _typical_frame(log, basis) -> int:
    from modalinfo.ordering import fitting_error

    total = fitting_error(log, basis).total
    return int(np.argsort(total, kind="stable")[total.size // 2])


def _panel(ax, comp, title, target):
    from modalinfo.ordering.compare import plot_comparison

    plot_comparison(comp, ax, target=target, title=title)
    handles, labels = ax.get_legend_handles_labels()
    labels = [LABELS.get(lbl.replace(" (floor)", ""), lbl) + (" (floor)" if "floor" in lbl else "")
              for lbl in labels]
    ax.legend(handles, labels, fontsize=7)


def _rows(comp, targets: dict) -> list[str]:
    lines = []
    for e in comp.entries:
        row = [LABELS[e.name], str(PAPER.get(e.name, "-"))]
        row += [str(e.error.modes_to_reach(t, comp.frame)) for t in targets.values()]
        lines.append("| " + " | ".join(row) + " |")
    return lines


def make(out_dir: Path, log_path: Path | None) -> str:
    """Draw Figure 1 into ``out_dir`` and return the report section (Markdown)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from modalinfo.ordering.compare import basis_for_log, compare_orderings
    from modalinfo.telemetry.synthetic import kaos_like

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    log, source = load_log(log_path)
    bases: dict = {}
    bases["zernike"] = basis_for_log("zernike", log)
    gram = bases["zernike"].gram()
    ortho = float(np.abs(gram - np.eye(gram.shape[0])).max())
    mean_square = np.mean(np.asarray(log.coeffs, dtype=float) ** 2, axis=0)
    spread = float(mean_square.max() / mean_square.min())
    frame = _typical_frame(log, bases["zernike"])
    per_frame = compare_orderings(log, SPECS, frame=frame, units="waves2", seed=0, bases=bases)
    pooled = compare_orderings(log, SPECS, units="waves2", seed=0,
                               sample_budget=POOLED_BUDGET, bases=bases)
    open_log = kaos_like(n_frames=OPEN_LOOP_FRAMES, closed_loop=False, seed=0)
    open_comp = compare_orderings(open_log, SPECS, units="waves2", seed=0,
                                  sample_budget=POOLED_BUDGET // 2)

    # targets: the paper's 0.4 waves^2, and the error at which the standard Zernike order
    # needs 20 modes on our data (the same place on the curve as in the paper)
    def calibrated(comp):
        return float(comp.curve(comp.entries[0])[20])

    t_frame, t_pool, t_open = calibrated(per_frame), calibrated(pooled), calibrated(open_comp)
    fig, axes = plt.subplots(1, 3, figsize=(17, 4.8))
    _panel(axes[0], per_frame, f"(a) typical frame {frame} (per-frame orderings)", t_frame)
    _panel(axes[1], pooled, f"(b) average over {log.n_frames} frames (pooled orderings)",
           t_pool)
    _panel(axes[2], open_comp, f"(c) open loop, same turbulence ({OPEN_LOOP_FRAMES} frames)",
           t_open)
    fig.tight_layout()
    fig.savefig(out_dir / FIGURE_NAME, dpi=110)
    plt.close(fig)

    total_frame = float(per_frame.curve(per_frame.entries[0])[0])
    total_pool = float(pooled.curve(pooled.entries[0])[0])
    total_open = float(open_comp.curve(open_comp.entries[0])[0])
    head = ("| ordering | paper (0.4 waves^2) | our: 0.4 waves^2 | our: calibrated target |\n"
            "|---|---|---|---|")
    sections = []
    for name, comp, target, total in (
        (f"(a) typical frame {frame}", per_frame, t_frame, total_frame),
        (f"(b) average over {log.n_frames} frames", pooled, t_pool, total_pool),
        (f"(c) open loop, {OPEN_LOOP_FRAMES} frames", open_comp, t_open, total_open),
    ):
        sections.append(
            f"**{name}**: total variance dPhi(0) = {total:.3g} waves^2; calibrated target "
            f"{target:.3g} waves^2 = {100 * target / total:.1f}% of it.\n\n{head}\n"
            + "\n".join(_rows(comp, {"paper": PAPER_TARGET, "cal": target})) + "\n"
        )

    def need(comp, key, target):
        e = next(e for e in comp.entries if e.name == key)
        return e.error.modes_to_reach(target, comp.frame)

    # many frames: is the typical frame typical?
    sample_frames = np.linspace(0, log.n_frames - 1, N_FRAMES).astype(int)
    counts = {name: [] for name in LABELS}
    for f in sample_frames:
        comp = compare_orderings(log, SPECS, frame=int(f), units="waves2", seed=0, bases=bases)
        target = calibrated(comp)
        for e in comp.entries:
            counts[e.name].append(e.error.modes_to_reach(target, comp.frame))
    many = ["| ordering | median | quartiles | frames below 20 |", "|---|---|---|---|"]
    med = {}
    for name, vals in counts.items():
        v = np.asarray(vals)
        q1, q2, q3 = np.percentile(v, [25, 50, 75])
        med[name] = q2
        many.append(f"| {LABELS[name]} | {q2:.0f} | {q1:.0f}-{q3:.0f} | "
                    f"{int(np.sum(v < 20))}/{v.size} |")

    # stability: pooled orderings of 1 s windows and seeds; per-frame orderings of
    # consecutive frames (is a per-frame ordering usable from one frame to the next?)
    from modalinfo.ordering import ordering_stability

    window = int(round(log.rate)) if log.rate else log.n_frames // 4
    window = max(1, min(window, log.n_frames // 2))
    stab = ordering_stability(log, bases["zernike"], "mi_greedy", window=window,
                              seeds=(0, 1, 2), sample_budget=POOLED_BUDGET // 2)
    consecutive = ordering_stability(log[frame:frame + 10], bases["zernike"], "mi_greedy",
                                     window=1, seeds=())
    stab_text = (
        f"**Stability of the MI-greedy Zernike order.** Pooled over windows of {window} "
        f"frames ({stab.window_duration or 0:.2g} s): median Spearman rho "
        f"{np.median(stab.window_spearman):.2f} between consecutive windows (Kendall tau "
        f"{np.median(stab.window_kendall):.2f}, top-{stab.n_top} overlap "
        f"{np.median(stab.window_top_overlap):.2f}); across 3 subsampling seeds on the whole "
        f"log rho {np.median(stab.seed_spearman):.2f}. Per-frame orderings of 10 consecutive "
        f"frames from frame {frame}: median rho {np.median(consecutive.window_spearman):.2f}, "
        f"top-{consecutive.n_top} overlap {np.median(consecutive.window_top_overlap):.2f} "
        "from one frame to the next, so a per-frame MI ordering "
        + ("changes from frame to frame and could not be used as a fixed compression of a "
           "real-time loop."
           if np.median(consecutive.window_spearman) < 0.8
           else "is fairly stable from frame to frame.")
    )

    mi_z = need(per_frame, "zernike:mi_greedy", t_frame)
    mi_kl = need(per_frame, "kl-theory:mi_greedy", t_frame)
    var_z = need(per_frame, "zernike:variance", t_frame)
    pooled_n = {e.name: need(pooled, e.name, t_pool) for e in pooled.entries}
    open_n = {e.name: need(open_comp, e.name, t_open) for e in open_comp.entries}

    def verdict(n, ref=20):
        return "fewer than" if n < ref else ("as many as" if n == ref else "more than")

    reading = [
        f"On the typical frame the MI-ordered Zernikes need {mi_z} modes and the MI-ordered "
        f"K-L {mi_kl} to reach the error the standard order reaches with 20 (paper: 7 and "
        f"15). Over {N_FRAMES} frames spread through the log the medians are "
        f"{med['zernike:mi_greedy']:.0f} (MI Zernike) and {med['kl-theory:mi_greedy']:.0f} "
        f"(MI K-L): per-frame MI reordering needs {verdict(med['zernike:mi_greedy'])} the "
        f"standard 20 for Zernikes and {verdict(med['kl-theory:mi_greedy'])} 20 for K-L on "
        "this log.",
        f"The per-frame a_k^2 order needs {var_z} modes on the typical frame (median "
        f"{med['zernike:variance']:.0f}); for an orthonormal basis it is the exact per-frame "
        "optimum (the error is the sum of the dropped a_k^2; our 64-pixel Zernikes are "
        f"orthonormal to {ortho:.0%}), so it, not the standard order, is the baseline a "
        "per-frame "
        "reordering has to beat: "
        + ("MI order does not beat it here."
           if med["zernike:mi_greedy"] >= med["zernike:variance"]
           else "MI order beats it here, which a non-orthonormal sampled basis allows."),
        "Averaged over frames (pooled orderings) the orderings need "
        f"{min(pooled_n.values())}-{max(pooled_n.values())} modes (MI Zernike "
        f"{pooled_n['zernike:mi_greedy']}, MI K-L {pooled_n['kl-theory:mi_greedy']}, "
        f"data-PCA floor {pooled_n['kl-data:pca']}): a fixed ordering gains little on this "
        f"closed-loop log, whose mode variances span only a factor {spread:.1f} (max/min "
        "mean-square coefficient).",
        f"In open loop (same turbulence) the MI-ordered theoretical K-L needs "
        f"{open_n['kl-theory:mi_greedy']} modes and the data-PCA {open_n['kl-data:pca']}, "
        f"against {open_n['zernike:standard']} for standard Zernikes (MI Zernikes "
        f"{open_n['zernike:mi_greedy']})"
        + (": the K-L advantage is larger in open loop than in closed loop, consistent with "
           "the paper's interpretation that the loop flattens the structure K-L modes are "
           "built for."
           if open_n["zernike:standard"] - open_n["kl-theory:mi_greedy"]
           > pooled_n["zernike:standard"] - pooled_n["kl-theory:mi_greedy"]
           else "; the K-L advantage is not larger in open loop than in closed loop here."),
        "Differences from the paper's numbers are expected: the log is synthetic and "
        "KAOS-like, not the 2008 VTT data; one \"typical\" frame is a choice (ours: median "
        "total variance), which is why the spread over frames is given; and the MI "
        "estimator, its binning and the pupil sampling are ours.",
    ]
    elapsed = time.perf_counter() - start
    return f"""## Figure 1: fitting error vs number of modes (MI reordering)

![Figure 1]({FIGURE_NAME})

Input: {source}. Fitting error dPhi(n) = mean over the pupil of |Phi_n - Phi_ref|^2 with
Phi_ref the full {log.n_modes}-mode reconstruction, in waves^2 (64-pixel pupil; MI by the histogram
estimator; per-frame orderings use every pixel of the frame, pooled orderings
{POOLED_BUDGET} (frame, pixel) samples, seed 0). Curves: Zernike standard order (dotted
blue), theoretical K-L in MI order (dashed green), Zernike in MI order (solid red), as in
the paper; plus the data-PCA order (thin black, the mean-square floor of panels b and c;
on one frame it is only the log's PCA order) and the Zernike a_k^2 order of the frame
(grey dash-dot). Dots mark where each curve reaches the calibrated target (horizontal
line).

**Targets.** The paper's 0.4 waves^2 cannot be used as such: the whole residual of this
closed-loop log is only {total_pool:.2g} waves^2 on average ({total_frame:.2g} on the
typical frame), so 0.4 waves^2 is "reached" with 0 modes by every ordering (0.4 waves^2
= 16 rad^2 of residual would be an open loop, not a closed one). We therefore also use a
calibrated target: the error at which the standard Zernike order needs 20 modes on our
data, the same place on the reference curve as in the paper, and count how many modes
the other orderings need there (the paper's counts are 20, 15 and 7).

{chr(10).join(sections)}
**Per-frame orderings on {N_FRAMES} frames** evenly spread through the log (calibrated
target of each frame; modes needed):

{chr(10).join(many)}

{stab_text}

**Reading.** {" ".join(reading)}
_(computed in {elapsed:.1f} s)_
"""


def main(argv: list[str] | None = None) -> int:
    """Command line: draw the figure and print the report section."""
    return figure_main(argv, prog="python -m paper_figures.fig1_fitting_error",
                       description="Regenerate Figure 1 (fitting error).",
                       figure_name=FIGURE_NAME, make=make)


if __name__ == "__main__":
    sys.exit(main())
