"""Recorded flights without ROS: rosbag2 files, simulated scenarios, and the offline analysis.

- :mod:`.io`: reading and writing .mcap and .db3 bags; :mod:`.checksums`: their CRCs and checks.
- :mod:`.scenario`: Keplerian orbits and attitude histories as messages.
- :mod:`.analysis`: :func:`analyze_bag`; its parts :mod:`.reading`, :mod:`.planning`,
  :mod:`.worker`, :mod:`.model_state`, :mod:`.table`, :mod:`.outputs`, :mod:`.report`.
- :mod:`.replacing`: which outputs ``--overwrite`` may replace.
"""
