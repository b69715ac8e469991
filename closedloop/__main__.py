import sys

try:  # Ctrl-C while the package imports (numpy, numba): one line and 130, no traceback
    from closedloop.cli import main

    code = main()
except KeyboardInterrupt:
    sys.stderr.write("closedloop: interrupted\n")
    code = 130
sys.exit(code)
