"""The node's quality of service: the inputs' profile and the standard ``qos_overrides``
parameters of every publisher and subscription (docs/node.md, "Quality of service")."""

from __future__ import annotations

from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions

from adbsat_ros.estimator.parameters import unknown_parameter

#: ``qos_overrides.<topic>.<publisher or subscription>.<history, depth or reliability>``.
OVERRIDES = QoSOverridingOptions.with_default_policies()
#: The values each overridden policy takes (rclpy's names, any case).
POLICY_VALUES = {
    "reliability": ("reliable", "best_effort", "system_default"),
    "history": ("keep_last", "keep_all", "system_default"),
}


def input_qos(depth: int) -> QoSProfile:
    """The inputs' QoS: BEST_EFFORT takes from RELIABLE and BEST_EFFORT publishers alike (a new
    profile each time: rclpy writes the overrides into the one it is given)."""
    return QoSProfile(depth=depth, reliability=ReliabilityPolicy.BEST_EFFORT)


def check_qos_values(node) -> None:
    """ValueError naming a start-up ``qos_overrides.*`` parameter whose value its policy does
    not take (a depth: a whole number >= 0)."""
    for name, parameter in getattr(node, "_parameter_overrides", {}).items():
        policy, value = name.rpartition(".")[2], parameter.value
        if not name.startswith("qos_overrides.") or policy not in (*POLICY_VALUES, "depth"):
            continue
        if policy == "depth":
            if not (isinstance(value, int) and not isinstance(value, bool) and value >= 0):
                raise ValueError(f"parameter {name}: a whole number >= 0, got {value!r}")
        elif str(value).lower() not in POLICY_VALUES[policy]:
            allowed = ", ".join(POLICY_VALUES[policy])
            raise ValueError(f"parameter {name}: one of {allowed}, got {value!r}")


def check_qos_overrides(node) -> None:
    """ValueError naming a start-up ``qos_overrides.*`` parameter that no publisher or
    subscription of ``node`` declared (a misspelt topic or policy), with the closest name."""
    overrides = getattr(node, "_parameter_overrides", {})  # (rclpy's start-up values)
    declared = [f"qos_overrides.{n}" for n in node.get_parameters_by_prefix("qos_overrides")]
    for name in overrides:
        if name.startswith("qos_overrides.") and name not in declared:
            raise ValueError(unknown_parameter(name, declared))
