import sys

from modalinfo.cli import main

sys.exit(main())
