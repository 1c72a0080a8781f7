"""The mesh as a visualization_msgs/Marker (triangle list), each panel coloured by its c_p.

Slow for large meshes: the node publishes it at a low rate, only while it has a subscriber.
"""

from __future__ import annotations

from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

from adbsat_ros.plotting.panels import panel_colours


def panel_marker(mesh, coefficients, frame_id: str, stamp) -> Marker:
    """A TRIANGLE_LIST Marker of ``mesh`` [m, body frame] coloured by ``coefficients``' c_p."""
    colours, _, _ = panel_colours(
        coefficients.cp, coefficients.cos_delta, coefficients.lit_fraction
    )
    marker = Marker()
    marker.header.frame_id = frame_id
    marker.header.stamp = stamp
    marker.ns = "panel_pressure"
    marker.id = 0
    marker.type = Marker.TRIANGLE_LIST
    marker.action = Marker.ADD
    marker.pose.orientation.w = 1.0
    marker.scale.x = marker.scale.y = marker.scale.z = 1.0
    marker.color.a = 1.0
    marker.points = [
        Point(x=float(x), y=float(y), z=float(z)) for x, y, z in mesh.vertices.reshape(-1, 3)
    ]
    per_panel = [ColorRGBA(r=float(r), g=float(g), b=float(b), a=1.0) for r, g, b, _ in colours]
    marker.colors = [c for c in per_panel for _ in range(3)]
    return marker
