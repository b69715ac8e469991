"""CPU time per table1 frame of the closedloop tree on ``PYTHONPATH`` (old vs new, same session).

Run it from each tree, alternating, so that the machine's drift hits both::

    for r in 1 2 3 4 5; do for w in OLD NEW; do
        (cd $w && PYTHONPATH=$w python /path/to/bench_table1_cpu.py 200 3); done; done

Prints one line: the tree's path and ``repeats`` CPU milliseconds per frame (no prediction,
no budget; the model is built once and the loop compiled by a 0.01 s warm-up run). Only
the public API is used (``closedloop.LoopModel``, ``presets``, ``simulate``), so any two
versions of the tree can be compared.
"""

import os
import sys
import time

from closedloop import LoopModel, presets, simulate


def main(frames: int, repeats: int) -> list[float]:
    config = presets.get("table1")
    model = LoopModel(config)
    simulate(config, 0.01, model=model, progress=False)
    out = []
    for _ in range(repeats):
        t = time.process_time()
        simulate(config, frames * config.loop.time_step, model=model, progress=False)
        out.append((time.process_time() - t) / frames * 1e3)
    return out


if __name__ == "__main__":
    frames, repeats = (int(a) for a in sys.argv[1:3]) if len(sys.argv) > 2 else (200, 3)
    print(os.environ.get("PYTHONPATH", "."), " ".join(f"{x:.3f}" for x in main(frames, repeats)))
