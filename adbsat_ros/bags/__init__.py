"""Recorded flights without ROS: rosbag2 files, simulated scenarios, and the offline analysis.

Modules:

- :mod:`~adbsat_ros.bags.io`: reading and writing .mcap and .db3 bags with rosbags.
- :mod:`~adbsat_ros.bags.checksums`: the CRCs of the MCAP files written, and the checks of a
  bag's files before it is analysed.
- :mod:`~adbsat_ros.bags.scenario`: Keplerian orbits and attitude histories as messages.
- :mod:`~adbsat_ros.bags.analysis`: :func:`analyze_bag`, a bag replayed through the node's
  per-message handler on several processes; :mod:`~adbsat_ros.bags.reading`,
  :mod:`~adbsat_ros.bags.planning`, :mod:`~adbsat_ros.bags.worker`,
  :mod:`~adbsat_ros.bags.model_state`, :mod:`~adbsat_ros.bags.table`,
  :mod:`~adbsat_ros.bags.outputs` and :mod:`~adbsat_ros.bags.report` are its parts.
- :mod:`~adbsat_ros.bags.replacing`: which outputs a path holds (what ``--overwrite`` may
  replace).

Imports the estimator and below, no ROS.
"""
