"""Child scripts that drop an interrupt in a C callback: one copy for the Ctrl-C tests.

For tests/common/test_ctrl_c_compile_fix55a.py and
tests/paper_figures/test_interrupt_compile_read56.py. References from outside the code:
the operating system's signal (``os.kill`` of the process's own signal, so that
Python's handler runs at the next bytecode, which is the callback's: the race made
deterministic), a real numba compile (llvmlite's ``ctypes`` object-cache callback) and
libc's ``qsort`` calling a ``ctypes`` callback. No time is asserted.
"""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Runs ``python -m {module} ARGS`` with numba's object-cache hook sending SIGINT (or the
#: signal named by the environment's SIG) to its own process at its AT-th call: Python's
#: handler raises at the hook's next bytecode, inside llvmlite's ctypes callback, where a
#: real Ctrl-C during LLVM's codegen lands.
COMPILE_SIGNALLED = textwrap.dedent("""
    import os, runpy, signal, sys
    from numba.core import codegen
    hook = codegen.JITCodeLibrary._object_compiled_hook.__func__
    calls = []
    def signalled(cls, ll_module, buf):
        calls.append(1)
        if len(calls) == int(os.environ["AT"]):
            os.kill(os.getpid(), getattr(signal, os.environ.get("SIG", "SIGINT")))
        return hook(cls, ll_module, buf)
    codegen.JITCodeLibrary._object_compiled_hook = classmethod(signalled)
    sys.argv = ["{prog}", *sys.argv[1:]]
    runpy.run_module("{module}", run_name="__main__", alter_sys=True)
""")


def compile_signalled(module: str, prog: str = "modalinfo") -> str:
    """Source of a ``python -c`` child: :data:`COMPILE_SIGNALLED` for ``module``."""
    return COMPILE_SIGNALLED.replace("{module}", module).replace("{prog}", prog)


def callback_interrupted(setup: str, raise_it: str, caught: str, report: str) -> str:
    """Source of a ``python -c`` child raising an interrupt in a ``ctypes`` callback.

    ``setup`` (lines of Python) runs first; ``raise_it`` is the statement that raises
    inside the first call of libc ``qsort``'s comparison, the way a Ctrl-C lands there;
    Python code then runs on after the C call (sleeping 2 s at most, which gives the
    GIL to a delivering thread). ``report`` (lines) runs in ``except caught as exc:``;
    "ran on" on stdout says the interrupt was dropped.
    """
    body = "\n".join([
        "import ctypes, ctypes.util, os, signal, sys, time",
        "from modalinfo.common.startup import keep_interrupts",
        textwrap.dedent(setup).strip("\n"),
        "libc = ctypes.CDLL(ctypes.util.find_library('c'))",
        "CMP = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ctypes.c_int),",
        "                       ctypes.POINTER(ctypes.c_int))",
        "raised = []",
        "def compare(a, b):",
        "    if not raised:",
        "        raised.append(1)",
        f"        {raise_it}",
        "    return a[0] - b[0]",
        "values = (ctypes.c_int * 5)(5, 1, 4, 2, 3)",
        "try:",
        "    libc.qsort(values, 5, ctypes.sizeof(ctypes.c_int), CMP(compare))",
        "    for _ in range(200):",
        "        time.sleep(0.01)",
        f"except {caught} as exc:",
        textwrap.indent(textwrap.dedent(report).strip("\n"), "    "),
        "print('ran on')",
    ])
    return body + "\n"


def child_env(**extra: str) -> dict[str, str]:
    """The children's environment: this checkout first, one thread each, no -W options."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), OPENBLAS_NUM_THREADS="1",
               NUMBA_NUM_THREADS="1", OMP_NUM_THREADS="1", **extra)
    env.pop("PYTHONWARNINGS", None)
    return env
