import sys

try:  # Ctrl-C while the package imports (numpy, numba): one line and 130, no traceback
    from modalinfo.cli import main

    code = main()
except KeyboardInterrupt:
    sys.stderr.write("modalinfo: interrupted\n")
    code = 130
sys.exit(code)
