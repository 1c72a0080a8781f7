"""Test-wide settings: keep ROS 2 discovery on this machine and on a domain of this run's own."""

import os

# Default Fast DDS discovery multicasts out of the machine: keep it on localhost.
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
# One ROS domain per test run (0-101 are valid), so parallel runs do not see each other.
os.environ.setdefault("ROS_DOMAIN_ID", str(10 + os.getpid() % 90))
