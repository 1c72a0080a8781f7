"""Run the command line as ``python -m adbsat_ros.cli``."""

import sys

from adbsat_ros.cli import main

sys.exit(main())
