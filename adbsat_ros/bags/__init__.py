"""Recorded flights without ROS: rosbag2 files, simulated scenarios, and the offline analysis.

Modules:

- :mod:`~adbsat_ros.bags.io`: reading and writing .mcap and .db3 bags with rosbags.
- :mod:`~adbsat_ros.bags.checksums`: the CRCs of the MCAP files written, and a bag's checks.
- :mod:`~adbsat_ros.bags.scenario`: Keplerian orbits and attitude histories as messages.
- :mod:`~adbsat_ros.bags.analysis`: :func:`analyze_bag`, a bag replayed through the node's
  per-message handler on several processes; its parts: :mod:`~adbsat_ros.bags.reading`,
  :mod:`~adbsat_ros.bags.planning`, :mod:`~adbsat_ros.bags.worker`,
  :mod:`~adbsat_ros.bags.model_state`, :mod:`~adbsat_ros.bags.table`,
  :mod:`~adbsat_ros.bags.outputs`, :mod:`~adbsat_ros.bags.report`.
- :mod:`~adbsat_ros.bags.replacing`: which outputs ``--overwrite`` may replace.
"""
