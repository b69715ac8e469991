"""``modalinfo fitting-error LOG``: compare orderings by their fitting-error curves (Figure 1).

Each ``basis:method`` in ``--orderings`` is ordered on the log (or on one frame with
``--frame``) and its fitting error dPhi(n), n = 1..27, computed; the command prints
dPhi at a few n and the modes needed to reach ``--target`` (and ``--fraction`` of the
total variance), and ``--plot`` draws the curves in the paper's Figure 1 styles
(Zernike standard dotted blue, K-L MI dashed green, Zernike MI solid red, data-PCA
floor thin black) with the target crossings marked. ``--quiet`` prints nothing on
success and needs ``--plot`` (as ``reorder --quiet`` needs ``--out``).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from modalinfo.cli import CommandError
from modalinfo.cli.cmd_reorder import (
    add_common_arguments,
    check_mi_time,
    check_pupil_memory,
    check_window_and_frame,
    file_basis,
    kl_geometry_note,
    load_analysed_log,
    refuse_frame_with_drop,
    resolve_mi_defaults,
)
from modalinfo.cli.shared import (
    _Renamed,
    apply_outliers,
    check_figure_output,
    queue_notes,
    quiet_printer,
    refuse_quiet_without_output,
    refuse_unused_ordering_options,
)
from modalinfo.common.files import shown_name
from modalinfo.common.quiet import quiet, recording

NAME = "fitting-error"
HELP = "Fitting error vs number of modes for several orderings (the paper's Figure 1)."

DEFAULT_ORDERINGS = "zernike:standard,kl-theory:mi_greedy,zernike:mi_greedy,kl-data:pca"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Fill the ``fitting-error`` parser."""
    # --quiet: nothing on stdout on success, as reorder / forecast / convert / synth; the
    # figure is then where the results go (it meant "no progress bar" and printed the
    # whole table, while its help said "needs --out FILE.json": fix57-d)
    add_common_arguments(parser, quiet_needs="--plot PNG")
    parser.add_argument("--orderings", default=DEFAULT_ORDERINGS, metavar="LIST",
                        help=f"comma-separated basis:method (default: {DEFAULT_ORDERINGS})")
    parser.add_argument("--error-units", dest="error_units", choices=("waves2", "rad2"),
                        default="waves2", help="units of the fitting error (default: waves2)")
    parser.add_argument("--units", dest="_retired_units", metavar="UNITS", action=_Renamed,
                        message="renamed --error-units; --units means the output units of "
                        "convert only", help="retired: use --error-units")
    parser.add_argument("--target", type=float, default=None, metavar="E",
                        help="target fitting error in --error-units (e.g. 0.4, the paper's)")
    parser.add_argument("--fraction", type=float, default=None, metavar="F",
                        help="also report modes to reach F x the total variance (0 < F < 1)")
    parser.add_argument("--plot", type=Path, default=None, metavar="PNG", help="draw the curves")


#: Gram eigenvalues of the sampled Zernikes farther than this from 1 get a note: the
#: fitting errors are the sampled pupil's, not the continuous ones (at the default 64
#: pixels Z2..Z28 span 0.993-1.07; at 16 pixels 0.876-1.494)
GRAM_NOTE = 0.1


def _sampling_note(args: argparse.Namespace, log) -> bool:
    """Note on stderr when ``--pupil-pixels`` samples the log's Zernikes far from orthonormal.

    At 16 pixels a log's total variance came out 6 % and dPhi(20) 12 % above the sums of
    its squared unit-RMS coefficients, with one more mode to reach a target, and no word
    (adversarial round 9 PART b, row L02).
    """
    import numpy as np

    from modalinfo.bases import Pupil, ZernikeBasis, indexing
    from modalinfo.cli.shared import queue_notes
    from modalinfo.common.chunked import gram

    if log.convention not in ("noll", "ansi", "fringe"):
        return False
    n, m = getattr(indexing, f"{log.convention}_to_zernike")(np.asarray(log.modes))
    matrix = np.asarray(ZernikeBasis(Pupil(args.pupil_pixels),
                                     modes=indexing.zernike_to_noll(n, m).tolist()).matrix)
    eig = np.linalg.eigvalsh(gram(matrix) / matrix.shape[0])  # gram: Ctrl-C between chunks
    worst = float(max(1.0 - eig[0], eig[-1] - 1.0))
    if worst > GRAM_NOTE:
        queue_notes(args, [
            f"on a {args.pupil_pixels}-pixel pupil the sampled Zernikes are not orthonormal "
            f"(Gram eigenvalues {eig[0]:.3g}-{eig[-1]:.3g}): the fitting errors are the "
            f"sampled pupil's and may differ from the continuous ones by up to "
            # "(64: within 7 %)" held for Z2..Z28 only, and was said after 100 or 160
            # pixels to logs of 1,000-3,000 modes (adversarial round 53 PART b, W16 / W18)
            f"{100 * worst:.0f} %; more --pupil-pixels than {args.pupil_pixels} bring them "
            "closer"])
        return True
    return False


def _pupil_sampling_note(args: argparse.Namespace, caught: list) -> None:
    """One note for the library's ``PupilSamplingWarning`` s (one per basis), the worst.

    Said in the command's words (``--pupil-pixels``), once, and not when
    :func:`_sampling_note` already said the sampled Zernikes are far from orthonormal.
    """
    from modalinfo.cli.shared import queue_notes

    if not caught:
        return
    w = max(caught, key=lambda c: abs(c.difference))
    own = [c for c in caught if c.suggested_pixels == 0]
    if own:  # an obscured pupil: no --pupil-pixels helps (round 37 PART a, S1-S8)
        queue_notes(args, [
            f"the bases are not orthonormal on this obscured pupil (max |gram - I| "
            f"{max(c.pupil_deviation for c in own):.2g} on the continuous annulus): the "
            f"fitting errors are this pupil's, up to {100 * w.difference:+.1f} % (at {w.n_at} "
            "modes) from the sums of the squared coefficients, which are not; a finer "
            "--pupil-pixels does not change this"])
        return
    queue_notes(args, [
        f"on a {w.n_pixels}-pixel pupil the sampled bases are not orthonormal (max |gram - I| "
        f"{max(c.gram_deviation for c in caught):.2g}): the fitting errors are the sampled "
        f"pupil's, up to {100 * w.difference:+.1f} % (at {w.n_at} modes) from the sums of the "
        f"squared coefficients of the continuous modes; --pupil-pixels "
        f"{max(c.suggested_pixels for c in caught)} brings the Gram error below 0.01"])


def _refuse_unused_options(args: argparse.Namespace, specs) -> None:
    """Refuse options that no ordering of ``--orderings`` uses, before their defaults.

    ``--estimator``, ``--budget`` and ``--seed`` act on the MI orderings (mi_greedy,
    mi_marginal) only, ``--outer-scale`` on the ``kl-theory`` basis only: given without
    one, the value was used by nothing and the user believed it applied, where
    ``reorder`` refuses the same options (round 36 PART b, F01-F07). A ``zernike:pca``
    or ``kl-theory:pca`` is refused here too, before the log is read: it failed after
    the work with the API's remedy (fix38-e).
    """
    given = [name for name, value in (("estimator", args.estimator),
                                      ("sample_budget", args.budget), ("seed", args.seed))
             if value is not None]
    refuse_unused_ordering_options([m for _, m in specs], given, basis=[b for b, _ in specs],
                                   chosen=f"--orderings {args.orderings}", noun="orderings")
    if args.outer_scale is not None and not any(b == "kl-theory" for b, _ in specs):
        raise CommandError(f"--outer-scale applies to the kl-theory basis (the K-L of a von "
                           f"Karman model); --orderings {args.orderings} uses none: drop it")


def run(args: argparse.Namespace) -> int:
    """Compute the curves, print the table (not with ``--quiet``), draw the plot."""
    from modalinfo.cli.shared import progress
    from modalinfo.ordering.compare import (
        KLGeometryWarning,
        compare_orderings,
        parse_specs,
        plot_comparison,
    )
    from modalinfo.ordering.cost import OrderingCostWarning
    from modalinfo.ordering.fitting_error import PupilSamplingWarning

    specs = parse_specs(args.orderings)
    _refuse_unused_options(args, specs)
    if args.estimator is None:  # the shared option's default (None lets reorder tell it was given)
        args.estimator = "histogram"
    resolve_mi_defaults(args)
    check_figure_output(args.plot, args.overwrite)
    seen = [tuple(s) for s in specs]
    twice = next((s for k, s in enumerate(seen) if s in seen[:k]), None)
    if twice is not None:
        raise CommandError(f"--orderings lists {':'.join(map(str, twice))} twice")
    if args.target is not None and not 0 <= args.target < math.inf:  # also refuses NaN
        raise CommandError(f"--target must be a finite number >= 0; got {args.target}")
    if args.fraction is not None and not 0 < args.fraction < 1:
        raise CommandError(f"--fraction must be in (0, 1); got {args.fraction}")
    # --quiet prints nothing: without --plot the curves would be thrown away (fix57-d)
    refuse_quiet_without_output(args, args.plot, "--plot PNG",
                                "the fitting-error table would be thrown away")
    refuse_frame_with_drop(args)
    log = load_analysed_log(args, mi=any(str(m).startswith("mi_") for _, m in specs),
                            zernike=any(b != "file" for b, _ in specs))
    check_window_and_frame(args, log)
    check_pupil_memory(args, log)
    noted = any(b in ("zernike", "kl-theory") for b, _ in specs) and _sampling_note(args, log)
    check_mi_time(args, log, n_orderings=sum(str(m).startswith("mi_") for _, m in specs))
    log, _ = apply_outliers(log, args, args.log)
    bases = {"file": file_basis(args, log)} if any(b == "file" for b, _ in specs) else None
    # OrderingCostWarning: check_mi_time said the estimate in flags, the library's words
    # are not repeated; KLGeometryWarning: kl_geometry_note says it in the command's words
    # (--outer-scale M); PupilSamplingWarning: said once below in the command's words
    # (--pupil-pixels), not once per basis. This thread's only: a catch_warnings block
    # swapped the process's filters and took other threads' warnings (fixes 41-c)
    with progress(args, len(specs), unit="ordering", desc="fitting-error") as advance, \
            quiet(OrderingCostWarning, KLGeometryWarning), \
            recording(PupilSamplingWarning) as caught:
        comp = compare_orderings(
            log, specs, frame=args.frame, units=args.error_units, estimator=args.estimator,
            sample_budget=args.budget, seed=args.seed, n_pixels=args.pupil_pixels,
            outer_scale=args.outer_scale, bases=bases, progress=advance,
        )
    sampled = [w.message for w in caught]
    if not noted:
        _pupil_sampling_note(args, sampled)
    if any(b == "kl-theory" for b, _ in specs):  # after the refusals (one line each)
        kl_geometry_note(args, log)
    targets = [args.target] if args.target is not None else []
    fractions = [args.fraction] if args.fraction is not None else []
    table = comp.table(targets=targets, fractions=fractions)
    if comp.frame is not None and getattr(args, "file_frame", None) is not None:
        # the file's frame number, not its index in the --max-frames subsample
        table = table.replace(f"frame {comp.frame}", f"frame {args.file_frame}", 1)
    say = quiet_printer(args)  # the table's lines, or nothing under --quiet
    say(table)
    first = comp.entries[0]
    total = float(comp.curve(first)[0])
    say(f"total variance dPhi(0) = {total:.4g} {args.error_units}")
    if args.target is not None and args.target >= total:
        above = (f"the target {args.target:g} {args.error_units} is above the total variance, "
                 "so it is reached with 0 modes; try --fraction")
        if args.quiet:  # a caution: on stderr then, as reorder's
            queue_notes(args, [above])
        else:
            print(f"note: {above}")
    if args.plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from modalinfo.common.plotting import drawable_rc, plot_text
        from modalinfo.ordering.compare import save_figure

        with drawable_rc():  # the user's matplotlibrc, less what cannot draw here
            fig, ax = plt.subplots(figsize=(7, 4.5))
            where = ("frame average" if comp.frame is None
                     else f"frame {getattr(args, 'file_frame', comp.frame)}")
            # the name as shown, never mathtext ("$x$.npz"): fix50-b
            plot_comparison(comp, ax, target=args.target,
                            title=f"{plot_text(args.log.name)}: {where}")
            try:
                save_figure(fig, args.plot, overwrite=args.overwrite)
            finally:
                plt.close(fig)
        say(f"figure written to {shown_name(args.plot)}")
    return 0
