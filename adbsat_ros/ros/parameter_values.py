"""Parameter values of their declared type: the node's parameters (no dynamic typing; an unknown
name stops the node at start-up) and the text ``adbsat-ros param set`` turns into a value.
"""

from __future__ import annotations

import math

import yaml
from rcl_interfaces.msg import ParameterDescriptor, ParameterType
from rclpy.exceptions import InvalidParameterTypeException
from rclpy.parameter import Parameter

from adbsat_ros.estimator.parameters import (
    PARAMETER_DEFAULTS,
    PARAMETERS,
    READ_ONLY_PARAMETERS,
    is_ros_parameter,
    parameter_kind,
    parameter_range_text,
    typed_parameter_value,
    unknown_parameter,
)

#: The range of a ROS integer parameter (int64).
INT64_MIN, INT64_MAX = -(2**63), 2**63 - 1


def declare_typed_parameters(node, managed: bool) -> None:
    """Declare every parameter of :data:`PARAMETERS` on ``node``, typed at start-up and on change.

    ValueError: ``"parameter NAME: ..."`` for another type or an unknown name.
    """
    # rclpy keeps the start-up values by name here (no public accessor in Jazzy)
    overrides = getattr(node, "_parameter_overrides", {})
    for name in [n for n in overrides if n in PARAMETER_DEFAULTS]:
        overrides[name] = Parameter(name, value=typed_parameter_value(name, overrides[name].value))
    for p in PARAMETERS:
        descriptor = ParameterDescriptor(
            description=p.text,
            additional_constraints=parameter_range_text(p.name),
            read_only=p.name in READ_ONLY_PARAMETERS and not managed,
        )
        try:
            node.declare_parameter(p.name, p.default, descriptor)
        except InvalidParameterTypeException:
            given = overrides.get(p.name)
            raise ValueError(
                f"parameter {p.name}: expected {parameter_kind(p.name)}, got "
                f"{None if given is None else given.value!r}"
            ) from None
    for name in overrides:
        if not node.has_parameter(name) and not is_ros_parameter(name):
            raise ValueError(unknown_parameter(name))
    node.add_pre_set_parameters_callback(typed_parameters)


def typed_parameters(parameters) -> list:
    """The pre-set callback: each of our parameters typed by the rule (else left, to be refused)."""
    return [
        Parameter(p.name, value=typed_parameter_value(p.name, p.value))
        if p.name in PARAMETER_DEFAULTS and p.type_ != Parameter.Type.NOT_SET
        else p
        for p in parameters
    ]


# ------------------------------------------------------------------------------- command line
_ELEMENT_TYPES = {
    ParameterType.PARAMETER_BOOL_ARRAY: ParameterType.PARAMETER_BOOL,
    ParameterType.PARAMETER_INTEGER_ARRAY: ParameterType.PARAMETER_INTEGER,
    ParameterType.PARAMETER_DOUBLE_ARRAY: ParameterType.PARAMETER_DOUBLE,
    ParameterType.PARAMETER_STRING_ARRAY: ParameterType.PARAMETER_STRING,
}


def _integer(name: str, text: str) -> int:
    """An integer parameter's value, within int64 (``32.0`` and ``1e3`` are whole numbers too)."""
    try:
        value = int(text, 10)
    except ValueError:
        try:
            number = float(text)
        except ValueError:
            number = math.nan
        if not (math.isfinite(number) and number.is_integer()):
            raise ValueError(f"{name} takes a whole number (integer), got {text!r}")
        value = int(number)
    if not INT64_MIN <= value <= INT64_MAX:
        raise ValueError(
            f"{name}: {text} is outside the range of a ROS integer parameter "
            f"[{INT64_MIN}, {INT64_MAX}]"
        )
    return value


def _double(name: str, text: str) -> float:
    """A double parameter's value (``2e2``, ``200``, ``.inf``; the node checks its range)."""
    try:
        return float(text)
    except ValueError:
        value = yaml.safe_load(text) if text.strip() else None
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            return float(value)
        raise ValueError(f"{name} takes a number (double), got {text!r}")


def _bool(name: str, text: str) -> bool:
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        value = None
    if not isinstance(value, bool):
        raise ValueError(f"{name} takes true or false, got {text!r}")
    return value


def _scalar(name: str, text: str, kind: int):
    if kind == ParameterType.PARAMETER_STRING:
        return text
    if kind == ParameterType.PARAMETER_BOOL:
        return _bool(name, text.strip())
    if kind == ParameterType.PARAMETER_INTEGER:
        return _integer(name, text.strip())
    return _double(name, text.strip())


def _inferred(name: str, text: str):
    """A parameter of no fixed type read as YAML, as ``ros2 param set`` does."""
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        return text
    items = value if isinstance(value, list) else [value]
    if value is None or not all(isinstance(x, (bool, int, float, str)) for x in items):
        return text if not isinstance(value, list) else [str(x) for x in value]
    for x in items:
        if isinstance(x, int) and not isinstance(x, bool) and not INT64_MIN <= x <= INT64_MAX:
            _integer(name, str(x))
    if isinstance(value, list) and {type(x) for x in value} == {int, float}:
        return [float(x) for x in value]
    return value


def text_value(name: str, text: str, kind: int, dynamic: bool = False):
    """The value of parameter ``name`` from command-line ``text`` as ``ParameterType`` ``kind``.

    A list as a YAML flow list (``[0.1, 0, 0]``), ``dynamic`` as YAML.
    ValueError: no value of its type, or an integer beyond int64.
    """
    if dynamic or kind == ParameterType.PARAMETER_NOT_SET:
        return _inferred(name, text)
    element = _ELEMENT_TYPES.get(kind)
    if element is None:
        if kind == ParameterType.PARAMETER_BYTE_ARRAY:
            raise ValueError(f"{name}: a byte array cannot be set from the command line")
        return _scalar(name, text, kind)
    try:
        items = yaml.load(text, Loader=yaml.BaseLoader)  # (every item as the text it is)
    except yaml.YAMLError:
        items = None
    if not isinstance(items, list) or not all(isinstance(x, str) for x in items):
        raise ValueError(f"{name} takes a list such as [1.0, 2.0], got {text!r}")
    return [_scalar(f"{name}[{i}]", x, element) for i, x in enumerate(items)]
