"""Reading and writing rosbag2 files (.mcap and .db3) without ROS, with ``rosbags``. The one
place that knows message layouts in bags. Stamps are integer nanoseconds."""

from __future__ import annotations

import contextlib
import functools
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np
from rosbags.rosbag2 import Reader, StoragePlugin
from rosbags.serde import SerdeError
from rosbags.typesys import Stores, get_typestore

from adbsat_ros.bags import replacing
from adbsat_ros.bags.checksums import CheckedWriter
from adbsat_ros.messages.decoding import JOINT_STATE, ODOMETRY, QUATERNION_STAMPED

#: The message types of ROS 2 Jazzy (the project's distribution).
TYPESTORE = get_typestore(Stores.ROS2_JAZZY)

WRENCH_STAMPED = "geometry_msgs/msg/WrenchStamped"
DIAGNOSTIC_ARRAY = "diagnostic_msgs/msg/DiagnosticArray"

#: Storage names accepted on the command line -> rosbags storage plugin.
STORAGES = {
    "mcap": StoragePlugin.MCAP,
    "sqlite3": StoragePlugin.SQLITE3,
    "db3": StoragePlugin.SQLITE3,
}
#: rosbag2 metadata format version written.
BAG_VERSION = 9
_NS = 1_000_000_000

_T = TYPESTORE.types
_Time = _T["builtin_interfaces/msg/Time"]
_Header = _T["std_msgs/msg/Header"]
_Vector3 = _T["geometry_msgs/msg/Vector3"]
_Point = _T["geometry_msgs/msg/Point"]
_Quaternion = _T["geometry_msgs/msg/Quaternion"]


class BagError(Exception):
    """A bag that cannot be read or written as asked; the message names the file or topic."""


# --------------------------------------------------------------------------------- stamps
def time_message(stamp_ns: int):
    """builtin_interfaces/Time of an integer nanosecond stamp (negative stamps not allowed)."""
    stamp_ns = int(stamp_ns)
    if stamp_ns < 0:
        raise ValueError(f"stamp {stamp_ns} ns is negative")
    sec, nanosec = divmod(stamp_ns, _NS)
    return _Time(sec=sec, nanosec=nanosec)


def _header(stamp, frame_id: str):
    if not isinstance(stamp, _Time):
        stamp = time_message(stamp)
    return _Header(stamp=stamp, frame_id=frame_id)


def _vector(cls, xyz):
    x, y, z = (float(v) for v in xyz)
    return cls(x=x, y=y, z=z)


# --------------------------------------------------------------------------------- builders
def odometry_message(
    stamp,
    frame_id: str,
    child_frame_id: str,
    position,
    velocity,
    orientation_xyzw=(0.0, 0.0, 0.0, 1.0),
    angular_velocity=(0.0, 0.0, 0.0),
):
    """nav_msgs/Odometry: pose in ``frame_id`` [m], twist in ``child_frame_id`` [m/s, rad/s]."""
    x, y, z, w = (float(v) for v in orientation_xyzw)
    pose = _T["geometry_msgs/msg/Pose"](
        position=_vector(_Point, position), orientation=_Quaternion(x=x, y=y, z=z, w=w)
    )
    twist = _T["geometry_msgs/msg/Twist"](
        linear=_vector(_Vector3, velocity), angular=_vector(_Vector3, angular_velocity)
    )
    return _T[ODOMETRY](
        header=_header(stamp, frame_id),
        child_frame_id=child_frame_id,
        pose=_T["geometry_msgs/msg/PoseWithCovariance"](pose=pose, covariance=np.zeros(36)),
        twist=_T["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=np.zeros(36)),
    )


def quaternion_stamped_message(stamp, frame_id: str, quaternion_xyzw):
    """geometry_msgs/QuaternionStamped (x, y, z, w)."""
    x, y, z, w = (float(v) for v in quaternion_xyzw)
    return _T[QUATERNION_STAMPED](
        header=_header(stamp, frame_id), quaternion=_Quaternion(x=x, y=y, z=z, w=w)
    )


def wrench_stamped_message(stamp, frame_id: str, force, torque):
    """geometry_msgs/WrenchStamped: force [N] and torque [N m] (or coefficients) in ``frame_id``."""
    wrench = _T["geometry_msgs/msg/Wrench"](
        force=_vector(_Vector3, force), torque=_vector(_Vector3, torque)
    )
    return _T[WRENCH_STAMPED](header=_header(stamp, frame_id), wrench=wrench)


def joint_state_message(stamp, frame_id: str, names, positions, velocities=(), efforts=()):
    """sensor_msgs/JointState: positions [rad or m], velocities, efforts."""
    return _T[JOINT_STATE](
        header=_header(stamp, frame_id),
        name=[str(n) for n in names],
        position=np.asarray(positions, dtype=float).reshape(-1),
        velocity=np.asarray(velocities, dtype=float).reshape(-1),
        effort=np.asarray(efforts, dtype=float).reshape(-1),
    )


def diagnostic_status(level: int, name: str, message: str, hardware_id: str, values: dict):
    """diagnostic_msgs/DiagnosticStatus with every value as text (as the node sends them)."""
    kv = _T["diagnostic_msgs/msg/KeyValue"]
    return _T["diagnostic_msgs/msg/DiagnosticStatus"](
        level=int(level),
        name=name,
        message=message,
        hardware_id=hardware_id,
        values=[kv(key=str(k), value=str(v)) for k, v in values.items()],
    )


def diagnostic_array_message(stamp, statuses):
    """diagnostic_msgs/DiagnosticArray holding the given DiagnosticStatus messages."""
    return _T[DIAGNOSTIC_ARRAY](header=_header(stamp, ""), status=list(statuses))


def serialize(msg) -> bytes:
    """CDR bytes of a message built here."""
    return TYPESTORE.serialize_cdr(msg, msg.__msgtype__)


def deserialize(raw, msgtype: str):
    """A message from CDR bytes (types of ROS 2 Jazzy)."""
    return TYPESTORE.deserialize_cdr(raw, msgtype)


#: A geometry_msgs/QuaternionStamped or a nav_msgs/Odometry from CDR bytes (raises for others).
deserialize_attitude = functools.partial(TYPESTORE.deserialize_cdr, typename=QUATERNION_STAMPED)
deserialize_odometry = functools.partial(TYPESTORE.deserialize_cdr, typename=ODOMETRY)


def deserialize_joint_state(raw):
    """A sensor_msgs/JointState from CDR bytes; up to 15 bytes after the last field are read past
    (rclpy leaves up to 12 there, rosbags refuses more than 3)."""
    try:
        return TYPESTORE.deserialize_cdr(raw, JOINT_STATE)
    except SerdeError as exc:
        for tail in (4, 8, 12):
            if len(raw) > tail + 4:
                with contextlib.suppress(SerdeError):
                    return TYPESTORE.deserialize_cdr(raw[:-tail], JOINT_STATE)
        raise exc from None


def joint_state_cdr(stamp, frame_id: str, names, positions, efforts) -> bytes:
    """CDR bytes of a JointState without velocities (``stamp``: sec, nanosec), by rosbags."""
    time = _Time(sec=int(stamp.sec), nanosec=int(stamp.nanosec))
    return bytes(serialize(joint_state_message(time, frame_id, names, positions, (), efforts)))


# --------------------------------------------------------------------------------- reading
def open_bag(path) -> Reader:
    """Open a rosbag2 (directory or .mcap/.db3) for reading; BagError naming a bad path."""
    path = Path(path)
    if not path.exists():
        raise BagError(f"input bag {path}: no such file or directory")
    try:
        reader = Reader(path)
        reader.open()
    except Exception as exc:  # rosbags raises ReaderError, sqlite/apsw, struct and OS errors here
        raise BagError(
            f"input bag {path}: cannot be read ({type(exc).__name__}: {exc}); "
            "is it a rosbag2 (.mcap or .db3) and complete?"
        ) from None
    return reader


def storage_plugin(storage: str) -> StoragePlugin:
    """The rosbags storage plugin for 'mcap' or 'sqlite3' ('db3')."""
    try:
        return STORAGES[str(storage).lower()]
    except KeyError:
        raise ValueError(f"storage {storage!r}: expected one of mcap, sqlite3") from None


# --------------------------------------------------------------------------------- writing
class BagWriter:
    """A rosbag2 writer building the bag beside ``path`` (:meth:`commit`, :meth:`discard`).
    ``storage``: ``'mcap'``/``'sqlite3'``; ``overwrite`` replaces a rosbag2 bag only, on commit."""

    def __init__(self, path, storage: str = "mcap", overwrite: bool = False):
        self.path = Path(path)
        self.storage = storage_plugin(storage)
        if self.path.exists() and not overwrite:
            raise BagError(
                f"output bag {self.path}: already exists (choose another name, or overwrite it: "
                "--overwrite)"
            )
        _check_replaceable(self.path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self._tmp_parent = Path(
            tempfile.mkdtemp(prefix=f".{self.path.name}.", suffix=".partial", dir=self.path.parent)
        )
        self._writer = CheckedWriter(
            self._tmp_parent / self.path.name, version=BAG_VERSION, storage_plugin=self.storage
        )
        self._writer.open()
        self._connections = {}
        self.count = 0

    def connection(
        self, topic: str, msgtype: str, msgdef: str | None = None, digest: str | None = None
    ):
        """The connection of (topic, msgtype), added on first use (Jazzy definitions by default)."""
        key = (topic, msgtype)
        conn = self._connections.get(key)
        if conn is None:
            # keep the recorded definition
            if (msgdef and digest) or msgtype not in TYPESTORE.types:
                conn = self._writer.add_connection(
                    topic, msgtype, msgdef=msgdef or "", rihs01=digest or ""
                )
            else:
                conn = self._writer.add_connection(topic, msgtype, typestore=TYPESTORE)
            self._connections[key] = conn
        return conn

    def write_raw(self, connection, t_ns: int, raw) -> None:
        """Write serialized bytes on a connection at log time t_ns."""
        self._writer.write(connection, int(t_ns), raw)
        self.count += 1

    def write(self, topic: str, t_ns: int, msg) -> None:
        """Serialize a message built here and write it on ``topic``."""
        self.write_raw(self.connection(topic, msg.__msgtype__), t_ns, serialize(msg))

    def commit(self, path=None) -> Path:
        """Close the bag, move it to its path (or ``path``, replacing a bag); returns where."""
        self._writer.close()
        path = self.path if path is None else Path(path)
        if path.exists() or path.is_symlink():
            _check_replaceable(path)
            shutil.rmtree(path)
        os.replace(self._tmp_parent / self.path.name, path)
        shutil.rmtree(self._tmp_parent, ignore_errors=True)
        return path

    def discard(self) -> None:
        """Drop everything written."""
        with contextlib.suppress(Exception):
            self._writer.close()  # closing a half-written bag may fail; it is deleted anyway
        shutil.rmtree(self._tmp_parent, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is not None:
            self.discard()
        elif self._tmp_parent.exists():
            self.commit()
        return False


def _check_replaceable(path: Path) -> None:
    """BagError naming what at ``path`` (if anything) is not a bag's: it is never removed."""
    if path.exists() or path.is_symlink():
        reason = replacing.refusal(path, "bag")
        if reason is not None:
            raise BagError(reason)


def write_bag(path, records, storage: str = "mcap", overwrite: bool = False) -> Path:
    """Write ``(topic, t_ns, msg)`` records into a new bag; returns its path."""
    with BagWriter(path, storage, overwrite) as writer:
        for topic, t_ns, msg in records:
            writer.write(topic, t_ns, msg)
    return Path(path)


def write_scenario_bag(
    messages,
    out_path,
    attitude_topic: str = "/attitude",
    state_topic: str = "/state",
    storage: str = "mcap",
    frame_id: str = "eci",
    overwrite: bool = False,
) -> Path:
    """Write ScenarioMessages as a bag: Odometry (twist the ECI velocity), QuaternionStamped. Log
    time = stamp, the state first at equal stamps."""
    states, attitudes = messages.states, messages.attitudes
    events = [(int(t), 0, i) for i, t in enumerate(states.stamps_ns)]
    events += [(int(t), 1, i) for i, t in enumerate(attitudes.stamps_ns)]
    events.sort()

    def records():
        for t_ns, kind, i in events:
            if kind == 0:
                position, velocity = states.position_eci[i], states.velocity_eci[i]
                pose = _orientation_at(attitudes, t_ns)
                msg = odometry_message(t_ns, frame_id, frame_id, position, velocity, pose)
                yield state_topic, t_ns, msg
            else:
                quaternion = attitudes.quaternion_xyzw[i]
                yield attitude_topic, t_ns, quaternion_stamped_message(t_ns, frame_id, quaternion)

    return write_bag(out_path, records(), storage, overwrite)


def _orientation_at(attitudes, t_ns):
    """The latest attitude at or before t_ns (or the first), for the Odometry pose orientation."""
    i = int(np.searchsorted(attitudes.stamps_ns, t_ns, side="right")) - 1
    return (
        attitudes.quaternion_xyzw[max(i, 0)] if len(attitudes.stamps_ns) else (0.0, 0.0, 0.0, 1.0)
    )
