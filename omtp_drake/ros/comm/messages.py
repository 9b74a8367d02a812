"""ROS 1 messages and services as plain Python classes (genpy's shapes, no ROS needed).

Every message class has ``__slots__`` (a misspelt field is an AttributeError, as
with genpy), takes its fields positionally in declaration order or by keyword,
compares by value and prints like ``rostopic echo``. A service type ``Foo`` has
``FooRequest`` and ``FooResponse``; ``ServiceProxy`` calls accept the request's
fields positionally (``proxy(True)``) or a request object.

:class:`Time` and :class:`Duration` are rospy's: seconds and nanoseconds,
``rospy.Time.now()`` (omtp_drake.ros.comm.rostime) is the cell's simulated time.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

from omtp_drake.errors import ConfigError

# ----------------------------------------------------------------------------- time


class _TimeBase:
    """Seconds and nanoseconds, as genpy's TVal."""

    __slots__ = ("secs", "nsecs")

    def __init__(self, secs: float = 0, nsecs: int = 0):
        if not math.isfinite(float(secs)):
            raise ConfigError(f"{type(self).__name__} needs finite seconds, got {secs!r}")
        total = int(round(float(secs) * 1e9)) + int(nsecs)
        self.secs, self.nsecs = divmod(total, 1_000_000_000)

    @classmethod
    def from_sec(cls, seconds: float):
        return cls(seconds)

    @classmethod
    def from_seconds(cls, seconds: float):
        return cls(seconds)

    def to_nsec(self) -> int:
        return self.secs * 1_000_000_000 + self.nsecs

    def to_sec(self) -> float:
        return self.to_nsec() / 1e9

    def is_zero(self) -> bool:
        return self.to_nsec() == 0

    def __lt__(self, other: _TimeBase) -> bool:
        return self.to_nsec() < _same(self, other).to_nsec()

    def __le__(self, other: _TimeBase) -> bool:
        return self.to_nsec() <= _same(self, other).to_nsec()

    def __gt__(self, other: _TimeBase) -> bool:
        return self.to_nsec() > _same(self, other).to_nsec()

    def __ge__(self, other: _TimeBase) -> bool:
        return self.to_nsec() >= _same(self, other).to_nsec()

    def _family(self) -> type[_TimeBase]:
        return Time if isinstance(self, Time) else Duration

    def __eq__(self, other: object) -> bool:
        return (
            isinstance(other, _TimeBase)
            and isinstance(other, self._family())
            and self.to_nsec() == other.to_nsec()
        )

    def __hash__(self) -> int:
        return hash((self._family().__name__, self.to_nsec()))

    def __repr__(self) -> str:
        return f"rospy.{type(self).__name__}[{self.to_nsec()}]"

    def __str__(self) -> str:
        return str(self.to_nsec())


def _same(a: _TimeBase, b: Any) -> _TimeBase:
    if not isinstance(b, a._family()):
        raise TypeError(f"cannot compare {type(a).__name__} with {type(b).__name__}")
    return b


class Duration(_TimeBase):
    """rospy.Duration: a signed time span."""

    __slots__ = ()

    def __add__(self, other: Any) -> Any:
        if isinstance(other, Duration):
            return Duration(0, self.to_nsec() + other.to_nsec())
        if isinstance(other, Time):
            return Time(0, self.to_nsec() + other.to_nsec())
        return NotImplemented

    def __sub__(self, other: Duration) -> Duration:
        if not isinstance(other, Duration):
            return NotImplemented
        return Duration(0, self.to_nsec() - other.to_nsec())

    def __neg__(self) -> Duration:
        return Duration(0, -self.to_nsec())

    def __mul__(self, k: float) -> Duration:
        return Duration(0, int(round(self.to_nsec() * float(k))))

    __rmul__ = __mul__

    def __truediv__(self, k: float) -> Duration:
        return Duration(0, int(round(self.to_nsec() / float(k))))


class Time(_TimeBase):
    """genpy's Time: a point in time (``rospy.Time`` adds ``now()``)."""

    __slots__ = ()

    def __init__(self, secs: float = 0, nsecs: int = 0):
        super().__init__(secs, nsecs)
        if self.to_nsec() < 0:
            raise ConfigError(f"Time cannot be negative, got {self.to_sec()} s")

    def __add__(self, other: Duration) -> Time:
        if not isinstance(other, Duration):
            return NotImplemented
        return Time(0, self.to_nsec() + other.to_nsec())

    __radd__ = __add__

    def __sub__(self, other: Any) -> Any:
        if isinstance(other, Time):
            return Duration(0, self.to_nsec() - other.to_nsec())
        if isinstance(other, Duration):
            return Time(0, self.to_nsec() - other.to_nsec())
        return NotImplemented


# ----------------------------------------------------------------------------- messages


class Message:
    """A ROS message: fields in ``__slots__`` order, defaults from ``_defaults``."""

    __slots__: ClassVar[tuple[str, ...]] = ()
    _type: ClassVar[str] = ""
    #: One factory per field, in ``__slots__`` order (float, str, list, a message class...).
    _defaults: ClassVar[tuple[Callable[[], Any], ...]] = ()

    def __init__(self, *args: Any, **kwargs: Any):
        names = self.__slots__
        if len(args) > len(names):
            raise TypeError(
                f"{self._type} takes at most {len(names)} fields ({', '.join(names)}), got {len(args)}"
            )
        unknown = sorted(set(kwargs) - set(names))
        if unknown:
            raise TypeError(f"{self._type} has no field {unknown[0]!r}; fields: {', '.join(names)}")
        given = dict(zip(names, args))
        for name in kwargs:
            if name in given:
                raise TypeError(f"{self._type}: field {name!r} given twice")
        given.update(kwargs)
        for name, default in zip(names, self._defaults):
            setattr(self, name, given[name] if name in given else default())

    def __getattr__(self, name: str) -> Any:
        # Only for a name that is no field (fields are slots): name the fields.
        raise AttributeError(
            f"{self._type} has no field {name!r}; fields: {', '.join(self.__slots__) or 'none'}"
        )

    def __eq__(self, other: object) -> bool:
        return type(other) is type(self) and all(
            getattr(self, n) == getattr(other, n) for n in self.__slots__
        )

    __hash__ = None  # type: ignore[assignment]  # mutable, as genpy's

    def __repr__(self) -> str:
        return _yaml(self, "")

    __str__ = __repr__


def _yaml(value: Any, indent: str) -> str:
    if isinstance(value, Message):
        if not value.__slots__:
            return "{}"
        lines = []
        for name in value.__slots__:
            field = getattr(value, name)
            if isinstance(field, Message) and field.__slots__:
                lines.append(f"{indent}{name}: \n{_yaml(field, indent + '  ')}")
            elif isinstance(field, list) and field and isinstance(field[0], Message):
                items = [f"{indent}  -\n{_yaml(x, indent + '    ')}" for x in field]
                lines.append(f"{indent}{name}: \n" + "\n".join(items))
            else:
                lines.append(f"{indent}{name}: {_yaml(field, indent)}")
        return "\n".join(lines)
    if isinstance(value, _TimeBase):
        return f"\n{indent}  secs: {value.secs}\n{indent}  nsecs: {value.nsecs}"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_yaml(x, indent) for x in value) + "]"
    return str(value)


# std_msgs


class Header(Message):
    __slots__ = ("seq", "stamp", "frame_id")
    _type = "std_msgs/Header"
    _defaults = (int, Time, str)


class Empty(Message):
    __slots__ = ()
    _type = "std_msgs/Empty"


class Bool(Message):
    __slots__ = ("data",)
    _type = "std_msgs/Bool"
    _defaults = (bool,)


class String(Message):
    __slots__ = ("data",)
    _type = "std_msgs/String"
    _defaults = (str,)


class Float64(Message):
    __slots__ = ("data",)
    _type = "std_msgs/Float64"
    _defaults = (float,)


class Int32(Message):
    __slots__ = ("data",)
    _type = "std_msgs/Int32"
    _defaults = (int,)


# geometry_msgs


class Point(Message):
    __slots__ = ("x", "y", "z")
    _type = "geometry_msgs/Point"
    _defaults = (float, float, float)


class Vector3(Message):
    __slots__ = ("x", "y", "z")
    _type = "geometry_msgs/Vector3"
    _defaults = (float, float, float)


class Quaternion(Message):
    """All zero by default, as in ROS (not the identity: set ``w = 1``)."""

    __slots__ = ("x", "y", "z", "w")
    _type = "geometry_msgs/Quaternion"
    _defaults = (float, float, float, float)


class Pose(Message):
    __slots__ = ("position", "orientation")
    _type = "geometry_msgs/Pose"
    _defaults = (Point, Quaternion)


class PoseStamped(Message):
    __slots__ = ("header", "pose")
    _type = "geometry_msgs/PoseStamped"
    _defaults = (Header, Pose)


class Twist(Message):
    __slots__ = ("linear", "angular")
    _type = "geometry_msgs/Twist"
    _defaults = (Vector3, Vector3)


class Transform(Message):
    __slots__ = ("translation", "rotation")
    _type = "geometry_msgs/Transform"
    _defaults = (Vector3, Quaternion)


class TransformStamped(Message):
    __slots__ = ("header", "child_frame_id", "transform")
    _type = "geometry_msgs/TransformStamped"
    _defaults = (Header, str, Transform)


class Pose2D(Message):
    __slots__ = ("x", "y", "theta")
    _type = "geometry_msgs/Pose2D"
    _defaults = (float, float, float)


class PoseArray(Message):
    __slots__ = ("header", "poses")
    _type = "geometry_msgs/PoseArray"
    _defaults = (Header, list)


# sensor_msgs / trajectory_msgs


class JointState(Message):
    __slots__ = ("header", "name", "position", "velocity", "effort")
    _type = "sensor_msgs/JointState"
    _defaults = (Header, list, list, list, list)


class JointTrajectoryPoint(Message):
    __slots__ = ("positions", "velocities", "accelerations", "effort", "time_from_start")
    _type = "trajectory_msgs/JointTrajectoryPoint"
    _defaults = (list, list, list, list, Duration)


class JointTrajectory(Message):
    __slots__ = ("header", "joint_names", "points")
    _type = "trajectory_msgs/JointTrajectory"
    _defaults = (Header, list, list)
