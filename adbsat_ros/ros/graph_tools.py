"""List, get and set a running node's parameters and print a topic's messages, without ``ros2``.

Each function makes its own context and node and waits at most ``timeout`` s for the other side.
"""

from __future__ import annotations

import contextlib
import functools
import os
import time

from rcl_interfaces.msg import ParameterType
from rclpy.exceptions import NameValidationException
from rclpy.parameter import Parameter, parameter_value_to_python
from rclpy.parameter_client import AsyncParameterClient
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.validate_namespace import validate_namespace
from rclpy.validate_node_name import validate_node_name

from adbsat_ros.bags.io import BagError
from adbsat_ros.bounds import errors_as
from adbsat_ros.ros.graph import GRAPH_POLL_S, absolute_topic, message_class, own_node
from adbsat_ros.ros.parameter_values import text_value

RELIABLE, BEST_EFFORT = ReliabilityPolicy.RELIABLE, ReliabilityPolicy.BEST_EFFORT


class ToolError(RuntimeError):
    """What went wrong, in one line (no such node, a timeout, a rejected value)."""


class BadInput(ToolError):
    """A command-line input that cannot be used (no ROS name, no value of its type), in one line."""


def checked_node_name(target: str) -> str:
    """``target`` if it is a valid ROS node name (``/ns/adbsat_node``), else BadInput naming it."""
    namespace, _, name = target.rpartition("/")
    try:
        validate_node_name(name)
        if namespace:
            validate_namespace(namespace if namespace.startswith("/") else "/" + namespace)
    except NameValidationException as exc:
        why = str(exc).splitlines()[0].rstrip(":").split(": ", 1)[-1]
        raise BadInput(f"node {target!r}: not a valid node name ({why})") from None
    return target


@contextlib.contextmanager
def tool_node():
    """``(node, spin)``: a node in a context of its own, taken down on exit, and ``spin()`` that
    spins it once."""
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    with own_node("adbsat_ros_tool") as (node, executor):
        yield node, functools.partial(executor.spin_once, timeout_sec=GRAPH_POLL_S)


#: Seconds after which a request with no answer is sent again: a server that has not yet
#: matched the client's reply reader drops its reply (Fast DDS: "failed to send response").
RESEND_S = 2.0


def _wait(spin, request, timeout: float, what: str):
    """The answer to ``request()``, resent every :data:`RESEND_S` until ``timeout`` s pass."""
    deadline = time.monotonic() + timeout
    futures = [request()]
    sent = time.monotonic()
    while not any(f.done() for f in futures):
        now = time.monotonic()
        if now > deadline:
            raise ToolError(f"{what}: no answer within {timeout:g} s")
        if now - sent > RESEND_S:
            futures.append(request())
            sent = now
        spin()
    return next(f for f in futures if f.done()).result()


@contextlib.contextmanager
def _parameters(target: str, timeout: float):
    """``(client, ask)`` of node ``target``'s parameter services; ``ask(request)``: the answer."""
    checked_node_name(target)
    with tool_node() as (node, spin):
        client = AsyncParameterClient(node, target)
        deadline = time.monotonic() + timeout
        while not client.services_are_ready():
            if time.monotonic() > deadline:
                raise ToolError(
                    f"node {target}: its parameter services did not appear within {timeout:g} s "
                    "(is it running, on this ROS_DOMAIN_ID?)"
                )
            spin()
        yield client, lambda request: _wait(spin, request, timeout, f"node {target}")


def list_parameters(target: str, timeout: float = 5.0) -> dict:
    """Every parameter of node ``target`` and its value (Python values), by name."""
    with _parameters(target, timeout) as (client, ask):
        names = ask(client.list_parameters).result.names
        values = ask(lambda: client.get_parameters(names)).values
        found = {n: parameter_value_to_python(v) for n, v in zip(names, values)}
        return dict(sorted(found.items()))


def get_parameter(target: str, name: str, timeout: float = 5.0):
    """The value of parameter ``name`` of node ``target``; ToolError if it has none."""
    with _parameters(target, timeout) as (client, ask):
        value = ask(lambda: client.get_parameters([name])).values
        if not value or value[0].type == ParameterType.PARAMETER_NOT_SET:
            raise ToolError(f"node {target} has no parameter {name!r}")
        return parameter_value_to_python(value[0])


def set_parameter(target: str, name: str, text: str, timeout: float = 5.0):
    """Set parameter ``name`` of node ``target`` to ``text`` read as its declared type; the value.

    BadInput: no node name, or ``text`` of another type. ToolError: rejected, unknown or no answer.
    """
    with _parameters(target, timeout) as (client, ask):
        described = ask(lambda: client.describe_parameters([name])).descriptors
        if not described or described[0].type == ParameterType.PARAMETER_NOT_SET:
            raise ToolError(f"node {target} has no parameter {name!r}")
        with errors_as(BadInput):
            value = text_value(name, text, described[0].type, described[0].dynamic_typing)
        parameter = Parameter(name, value=value)
        result = ask(lambda: client.set_parameters([parameter])).results[0]
        if not result.successful:
            raise ToolError(f"node {target} rejected {name}={text}: {result.reason}")
        return value


def message_text(message, indent: str = "") -> str:
    """A message as indented ``field: value`` lines (as ``ros2 topic echo`` prints)."""
    lines = []
    for field in message.get_fields_and_field_types():
        value = getattr(message, field)
        if hasattr(value, "get_fields_and_field_types"):
            lines.append(f"{indent}{field}:")
            lines.append(message_text(value, indent + "  "))
        elif (
            isinstance(value, (list, tuple))
            and value
            and hasattr(value[0], "get_fields_and_field_types")
        ):
            lines.append(f"{indent}{field}:")
            for item in value:
                body = message_text(item, indent + "  ").lstrip()
                lines.append(f"{indent}- {body}")
        else:
            if isinstance(value, bytes):  # (a byte field, e.g. a diagnostic level: its number)
                shown = value[0] if len(value) == 1 else list(value)
            else:
                shown = repr(value) if isinstance(value, str) else value
            lines.append(f"{indent}{field}: {shown}")
    return "\n".join(lines)


def echo(topic: str, count: int | None, timeout: float, write, stop=None) -> list:
    """Print the messages of ``topic`` until ``count`` came (None: until ``stop`` is set); the
    times [s, monotonic] they came at. With a ``count``, ends too when none comes for ``timeout`` s.

    ToolError: the topic is not in the graph within ``timeout`` s, or its type is not installed.
    """
    topic = absolute_topic(topic)

    def stopped() -> bool:
        return stop is not None and stop.is_set()

    with tool_node() as (node, spin):
        deadline = time.monotonic() + timeout
        kind = None
        while kind is None and not stopped():
            kinds = dict(node.get_topic_names_and_types()).get(topic)
            if kinds:
                kind = kinds[0]
            elif time.monotonic() > deadline:
                raise ToolError(f"topic {topic}: not in the ROS graph within {timeout:g} s")
            else:
                spin()
        if kind is None:
            return []
        with errors_as(ToolError, BagError):
            message_type = message_class(kind, topic)
        # as ros2 topic echo: reliable if every publisher is, else best effort (which takes both)
        publishers = node.get_publishers_info_by_topic(topic)
        reliable = all(p.qos_profile.reliability == RELIABLE for p in publishers)
        qos = QoSProfile(depth=10, reliability=RELIABLE if reliable else BEST_EFFORT)
        received = []
        node.create_subscription(
            message_type, topic, lambda m: received.append((time.monotonic(), m)), qos
        )
        times = []
        deadline = time.monotonic() + timeout
        while (count is None or len(times) < count) and not stopped():
            if count is not None and time.monotonic() > deadline:
                break
            spin()
            while received and (count is None or len(times) < count):
                came, message = received.pop(0)
                write(message_text(message) + "\n---")
                times.append(came)
                deadline = time.monotonic() + timeout
        return times
