"""Run the command line as ``python -m adbsat_ros.cli``."""

import sys

from . import main

sys.exit(main())
