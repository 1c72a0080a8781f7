"""Which of the node's optional outputs have subscribers, counted from matched events."""

from __future__ import annotations

import functools

from rclpy.event_handler import PublisherEventCallbacks

#: The optional outputs and the topics whose readers want each.
OUTPUTS = {
    "coefficients": ("coefficients",),
    "inertial": ("wrench_inertial", "acceleration"),
    "joint_torques": ("joint_torques",),
    "marker": ("panel_marker",),
}


class Readers:
    """Subscriber counts of the optional outputs' topics (``coefficients``, ``inertial``, ...)."""

    def __init__(self, create_publisher):
        self._create_publisher = create_publisher
        self.counts: dict = {}
        self.coefficients = self.inertial = self.joint_torques = self.marker = False

    def publisher(self, msg_type, topic: str, qos):
        """A publisher of ``topic``, its subscribers counted here."""
        publisher = self._create_publisher(
            msg_type,
            topic,
            qos,
            event_callbacks=PublisherEventCallbacks(
                matched=functools.partial(self._matched, topic)
            ),
        )
        self._set(topic, publisher.get_subscription_count())
        return publisher

    def _matched(self, topic: str, info) -> None:
        self._set(topic, info.current_count)

    def _set(self, topic: str, count: int) -> None:
        self.counts[topic] = count
        for output, topics in OUTPUTS.items():
            if topic in topics:
                setattr(self, output, any(self.counts.get(t, 0) > 0 for t in topics))
