"""What a bag analysis reports: the models' labels and topics, their summaries, the outcome.

Per-model topics ``NAMESPACE/LABEL/wrench`` and ``.../coefficients`` (label: :func:`check_label`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

#: Name of the node whose section a parameters file is read from, and whose logic is replayed.
NODE_NAME = "adbsat_node"
#: Namespace of the per-model output topics: NAMESPACE/LABEL/wrench and .../coefficients.
NAMESPACE = "/adbsat"
DIAGNOSTICS_TOPIC = "/diagnostics"
_LABEL_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def label_from_name(name: str) -> str:
    """A topic-safe label from a file stem: other characters to '_', a leading digit gets 'm'."""
    label = re.sub(r"[^A-Za-z0-9_]", "_", str(name)) or "model"
    return label if label[0].isalpha() else "m" + label


def check_label(label: str) -> str:
    """Return ``label`` if it can be a ROS topic name token, else raise ValueError naming it."""
    if not _LABEL_RE.match(label):
        raise ValueError(
            f"model label {label!r}: use letters, digits and '_' and start with a letter"
        )
    return label


@dataclass
class ModelSummary:
    """What one model produced: topics, triggers, wrenches and rejections by reason."""

    label: str
    wrench_topic: str
    coefficients_topic: str
    solar_topic: str
    total_topic: str
    joint_torques_topic: str
    triggers: int = 0
    wrenches: int = 0
    rejections: dict = field(default_factory=dict)
    first_rejection: dict = field(default_factory=dict)

    @classmethod
    def of_label(cls, label: str) -> "ModelSummary":
        """An empty summary of the model ``label``, with its topics."""
        topic = f"{NAMESPACE}/{label}"
        return cls(
            label,
            f"{topic}/wrench",
            f"{topic}/coefficients",
            f"{topic}/solar_wrench",
            f"{topic}/total_wrench",
            f"{topic}/joint_torques",
        )


@dataclass
class AnalysisReport:
    """Outcome of :func:`adbsat_ros.bags.analysis.analyze_bag`.

    ``error``: why the input could not be read to its end; ``seconds``: wall time [s] by phase.
    """

    input: Path
    outputs: dict = field(default_factory=dict)
    models: list = field(default_factory=list)
    messages_read: int = 0
    messages_total: int = 0
    error: str | None = None
    warnings: list = field(default_factory=list)
    seconds: dict = field(default_factory=dict)
    workers: int = 1
    chunks: int = 0
    skipped_chunks: int = 0
    skipped_messages: int = 0

    @property
    def partial(self) -> bool:
        """True if the input could not be read to its end."""
        return self.error is not None

    @property
    def wrenches(self) -> int:
        """Wrenches written, all models."""
        return sum(m.wrenches for m in self.models)

    def add_rejection_warnings(self, attitude_topic: str, state_topic: str) -> None:
        """Turn the models' rejections into warnings that say what was wrong with the input."""
        for summary in self.models:
            for reason, count in sorted(summary.rejections.items()):
                if reason == "no_state":
                    text = (
                        f"{count} messages on {attitude_topic} came before the first usable "
                        f"state on {state_topic}: no wrench for them"
                    )
                else:
                    first = summary.first_rejection.get(reason, "")
                    text = f"{count} inputs rejected ({reason}), first: {first}"
                self.warnings.append(f"model {summary.label}: {text}")
            if summary.triggers and not summary.wrenches:
                self.warnings.append(
                    f"model {summary.label}: no wrench computed from {summary.triggers} inputs"
                )
