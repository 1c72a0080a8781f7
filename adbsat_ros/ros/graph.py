"""The live bag tools' own rclpy context, message classes and topic names."""

from __future__ import annotations

import contextlib
import importlib

import rclpy
from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor

from adbsat_ros.bags.io import BagError

#: Seconds between two looks at the ROS graph while waiting for topics or subscribers.
GRAPH_POLL_S = 0.05


def message_class(msgtype: str, topic: str = ""):
    """The rclpy message class of a ROS type name; BagError if malformed or not installed."""
    where = f"topic {topic}: " if topic else ""
    parts = msgtype.split("/")
    if len(parts) == 2:  # 'pkg/Type' (ROS 1 style) -> pkg/msg/Type
        parts = [parts[0], "msg", parts[1]]
    if len(parts) != 3 or not all(parts):
        raise BagError(f"{where}message type {msgtype!r} is not of the form package/msg/Type")
    package, kind, name = parts
    try:
        module = importlib.import_module(f"{package}.{kind}")
        cls = getattr(module, name)
    except (ImportError, AttributeError):
        raise BagError(
            f"{where}message type {msgtype!r} is not installed in this Python environment "
            f"(no {package}.{kind}.{name}; install the package's ROS 2 wheel, "
            f"e.g. ros-jazzy-{package.replace('_', '-')})"
        ) from None
    return cls


@contextlib.contextmanager
def own_node(node_name: str):
    """``(node, executor)`` in an rclpy Context of their own; all shut down on exit."""
    context = Context()
    rclpy.init(context=context)  # (a Context of its own: rclpy installs no signal handlers)
    node = executor = None
    try:
        node = rclpy.create_node(node_name, context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        yield node, executor
    finally:
        if executor is not None:
            executor.shutdown(timeout_sec=1.0)
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown(context=context)


def absolute_topic(topic: str) -> str:
    """``topic`` with a leading slash."""
    topic = topic.strip()
    return topic if topic.startswith("/") else "/" + topic
