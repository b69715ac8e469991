"""What the figure scripts share: their log, report tables, outputs and command line."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Callable
from pathlib import Path

__all__ = ["log_or_kaos_like", "figure_main", "markdown_table", "save_png_pdf", "suffixed"]


def log_or_kaos_like(log_path: Path | None):
    """Return ``(log, description)``: the file's log, or the synthetic KAOS-like one."""
    if log_path is None:
        from modalinfo.telemetry.synthetic import kaos_like

        return kaos_like(seed=0), "synthetic `kaos_like(seed=0)` (closed loop, not real data)"
    from modalinfo.io import load

    return load(log_path), f"`{log_path}`"


def markdown_table(rows) -> str:
    """Markdown table of ``(quantity, paper, ours[, why])`` rows."""
    if rows and len(rows[0]) == 4:
        lines = ["| quantity | paper | ours | why they differ |", "|---|---|---|---|"]
        lines += [f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows]
    else:
        lines = ["| quantity | paper | ours |", "|---|---|---|"]
        lines += [f"| {a} | {b} | {c} |" for a, b, c, *_ in rows]
    return "\n".join(lines)


def suffixed(name: str, suffix: str) -> str:
    """``name`` with ``suffix`` before its extension (``fig1.png`` -> ``fig1_x.png``)."""
    stem, dot, ext = name.rpartition(".")
    return f"{stem}{suffix}{dot}{ext}"


def save_png_pdf(fig, out_dir: Path, png_name: str, pdf_name: str) -> list[Path]:
    """Save ``fig`` as PNG (110 dpi) and PDF in ``out_dir``, close it; return the paths."""
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    paths = [out_dir / png_name, out_dir / pdf_name]
    fig.savefig(paths[0], dpi=110)
    fig.savefig(paths[1])
    plt.close(fig)
    return paths


def figure_main(
    argv: list[str] | None,
    *,
    prog: str,
    description: str,
    figure_name: str,
    make: Callable[..., str],
    output_names: Callable[[str], list[str]] | None = None,
) -> int:
    """Stand-alone command line of one figure: draw it and print its report section.

    With ``output_names`` (the module's ``output_names(suffix)``), the command also takes
    ``--suffix`` (passed to ``make(out, log, suffix=...)``) and refuses to replace any
    of the files it lists; without it, only ``figure_name`` is checked.
    """
    parser = argparse.ArgumentParser(prog=prog, description=description)
    parser.add_argument("--log", type=Path, default=None,
                        help="modal log (default: synthetic kaos_like(seed=0))")
    parser.add_argument("--out", type=Path, default=Path("out"), help="output directory")
    parser.add_argument("--overwrite", action="store_true", help="replace an existing figure")
    if output_names is not None:
        parser.add_argument("--suffix", default="",
                            help="inserted before the extension of every output file name")
    args = parser.parse_args(argv)
    short = prog.rsplit(".", 1)[-1].split("_", 1)[0]
    names = [figure_name] if output_names is None else output_names(args.suffix)
    existing = [args.out / name for name in names if (args.out / name).exists()]
    if existing and not args.overwrite:
        sys.stderr.write(f"{short}: error: '{existing[0]}' exists; pass --overwrite\n")
        return 2
    if args.log is not None and not args.log.is_file():
        sys.stderr.write(f"{short}: error: log file '{args.log}' does not exist\n")
        return 2
    if output_names is None:
        print(make(args.out, args.log))
    else:
        print(make(args.out, args.log, suffix=args.suffix))
    return 0
