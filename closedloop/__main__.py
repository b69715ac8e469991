import sys

from modalinfo.common.startup import (
    exit_quietly,
    import_refusal,
    keep_interrupts,
    memory_refusal,
    one_line_warnings,
    require_current_folder,
    warning_refusal,
)

require_current_folder("closedloop")  # before the heavy imports (numba calls getcwd)
one_line_warnings("closedloop")  # a warning while the package loads: one line
keep_interrupts()  # a Ctrl-C dropped in a C callback (numba's compile) still ends it

try:  # Ctrl-C while the package imports (numpy, numba): one line and 130, no traceback
    from closedloop.cli import main

    code = main()
except KeyboardInterrupt:
    sys.stderr.write("closedloop: interrupted\n")
    code = 130
except (MemoryError, OSError) as exc:  # out of memory (ulimit -v) while loading numba
    code = memory_refusal("closedloop", exc)
except Warning as exc:  # raised as an error (-W error) while the package loads
    code = warning_refusal("closedloop", exc)
except ImportError as exc:  # NUMBA_NUM_THREADS=0, or a library not mapped (ulimit -v)
    code = import_refusal("closedloop", exc)
exit_quietly(code)
