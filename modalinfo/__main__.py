import os
import sys

try:  # a deleted current folder: numba's import of coverage calls os.getcwd()
    os.getcwd()
except FileNotFoundError:
    sys.stderr.write("modalinfo: error: the current folder no longer exists (deleted); "
                     "cd to an existing folder\n")
    sys.exit(2)

try:  # Ctrl-C while the package imports (numpy, numba): one line and 130, no traceback
    from modalinfo.cli import main

    code = main()
except KeyboardInterrupt:
    sys.stderr.write("modalinfo: interrupted\n")
    code = 130
except ImportError as exc:  # a dependency that refuses its environment (NUMBA_NUM_THREADS=0)
    if "NUMBA_" not in str(exc):
        raise
    sys.stderr.write(f"modalinfo: error: {exc}\n")
    code = 2
sys.exit(code)
