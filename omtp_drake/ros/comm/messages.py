"""ROS 1 messages and services as plain Python classes (genpy's shapes, no ROS needed),
made from their definitions: :func:`message`, :func:`service` and :func:`action` take
the ``.msg`` / ``.srv`` / ``.action`` text (field types, names, constants) and make the
classes, as genpy generates them from the same text.

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
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, ClassVar, Optional, cast

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


class _MessageType(type):
    if TYPE_CHECKING:

        def __getattr__(cls, name: str) -> Any:
            """A message class's constants (``MoveItErrorCodes.SUCCESS``), set from its definition."""


class Message(metaclass=_MessageType):
    """A ROS message: fields in ``__slots__`` order, defaults from ``_defaults`` (a class
    made by :func:`message` from its definition; a hand-written subclass may set them)."""

    __slots__: ClassVar[tuple[str, ...]] = ()
    _type: ClassVar[str] = ""
    #: One factory per field, in ``__slots__`` order (float, str, list, a message class...).
    _defaults: ClassVar[tuple[Callable[[], Any], ...]] = ()
    #: The ``.msg`` text the class was made from (a bag converts it to ROS 2's).
    _definition: ClassVar[str] = ""

    def __init__(self, *args: Any, **kwargs: Any):
        names = self.__slots__
        if not kwargs and len(args) == len(names):
            # Every field in order (Point(x, y, z): each pose of each published state).
            for name, value in zip(names, args):
                setattr(self, name, value)
            return
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


# ----------------------------------------------------------------------------- the factory

#: The classes made so far, by type name (``geometry_msgs/Pose``): a definition names them.
_TYPES: dict[str, type[Message]] = {}
#: The default of a field of each built-in type, as genpy's.
_BUILTIN: dict[str, Callable[[], Any]] = {
    **dict.fromkeys(("bool",), bool),
    **dict.fromkeys(("int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"), int),
    **dict.fromkeys(("byte", "char"), int),
    **dict.fromkeys(("float32", "float64"), float),
    "string": str,
    "time": Time,
    "duration": Duration,
}


def _field_type(package: str, name: str) -> Callable[[], Any]:
    """The default factory of a field of type ``name`` in a definition of ``package``."""
    if name.endswith("]"):
        # genpy reads a uint8[] (or char[]) as bytes, any other array as a list.
        return bytes if name.split("[")[0] in ("uint8", "char") else list
    if name in _BUILTIN:
        return _BUILTIN[name]
    full = "std_msgs/Header" if name == "Header" else name if "/" in name else f"{package}/{name}"
    if full not in _TYPES:
        raise NameError(f"a {package} definition names {full}, not defined yet (define or import it first)")
    return _TYPES[full]


def _parse(package: str, definition: str) -> tuple[list[str], list[Callable[[], Any]], dict[str, Any]]:
    """(field names, their default factories, constants) of a ``.msg`` text."""
    names: list[str] = []
    defaults: list[Callable[[], Any]] = []
    constants: dict[str, Any] = {}
    for raw in definition.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        kind, rest = line.split(None, 1)
        if "=" in rest:
            name, value = (x.strip() for x in rest.split("=", 1))
            constants[name] = value if kind == "string" else float(value) if "float" in kind else int(value)
        else:
            names.append(rest.strip())
            defaults.append(_field_type(package, kind))
    return names, defaults, constants


def _module() -> str:
    """The module that called the factory (its classes' ``__module__``, as if written there)."""
    return str(sys._getframe(2).f_globals["__name__"])


def message(
    type_name: str,
    definition: str = "",
    doc: str = "",
    module: str = "",
    attributes: Optional[dict[str, Any]] = None,
) -> type[Message]:
    """The class of the message ``type_name`` (``pkg/Name``) whose ``.msg`` text is
    ``definition``: its fields in order, their defaults from their types, its constants
    (and ``attributes``, class attributes of this project's own)."""
    package, name = type_name.split("/")
    names, defaults, constants = _parse(package, definition)
    namespace = {
        "__slots__": tuple(names),
        "_type": type_name,
        "_defaults": tuple(defaults),
        "_definition": definition,
        "__doc__": doc or f"``{type_name}``.",
        "__module__": module or _module(),
        **constants,
        **(attributes or {}),
    }
    cls = cast("type[Message]", _MessageType(name, (Message,), namespace))
    _TYPES[type_name] = cls
    return cls


def message_type(type_name: str) -> Optional[type[Message]]:
    """The message class made for ``type_name`` (``pkg/Name``), None when there is none (yet)."""
    return _TYPES.get(type_name)


class ServiceType:
    """A service: its request and response message classes."""

    _type: ClassVar[str] = ""
    _request_class: ClassVar[type[Message]]
    _response_class: ClassVar[type[Message]]


def service(type_name: str, definition: str) -> tuple[type[ServiceType], type[Message], type[Message]]:
    """(the service, its request, its response) of the ``.srv`` text ``definition`` (the
    request's fields, ``---``, the response's)."""
    request_text, response_text = definition.split("---")
    module = _module()
    request = message(f"{type_name}Request", request_text, module=module)
    response = message(f"{type_name}Response", response_text, module=module)
    namespace = {"_type": type_name, "_request_class": request, "_response_class": response}
    return (
        type(type_name.split("/")[1], (ServiceType,), {**namespace, "__module__": module}),
        request,
        response,
    )


def action(type_name: str, definition: str, doc: str = "") -> tuple[type[Message], ...]:
    """(the action type, its goal, result and feedback) of the ``.action`` text ``definition``
    (goal, ``---``, result, ``---``, feedback): ``SimpleActionClient(name, Action)`` takes the first."""
    module = _module()
    goal, result, feedback = (
        message(f"{type_name}{part}", text, module=module)
        for part, text in zip(("Goal", "Result", "Feedback"), definition.split("---"))
    )
    classes = {"_goal_class": goal, "_result_class": result, "_feedback_class": feedback}
    kind = message(f"{type_name}Action", doc=doc, module=module, attributes=classes)
    return kind, goal, result, feedback


# ----------------------------------------------------------------------------- std_msgs

Header = message("std_msgs/Header", "uint32 seq\ntime stamp\nstring frame_id")
Empty = message("std_msgs/Empty")
Bool = message("std_msgs/Bool", "bool data")
String = message("std_msgs/String", "string data")
Float64 = message("std_msgs/Float64", "float64 data")
Int32 = message("std_msgs/Int32", "int32 data")
MultiArrayDimension = message("std_msgs/MultiArrayDimension", "string label\nuint32 size\nuint32 stride")
MultiArrayLayout = message("std_msgs/MultiArrayLayout", "MultiArrayDimension[] dim\nuint32 data_offset")
Float64MultiArray = message("std_msgs/Float64MultiArray", "MultiArrayLayout layout\nfloat64[] data")

# ----------------------------------------------------------------------------- geometry_msgs

Point = message("geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z")
Vector3 = message("geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z")
Quaternion = message(
    "geometry_msgs/Quaternion",
    "float64 x\nfloat64 y\nfloat64 z\nfloat64 w",
    "All zero by default, as in ROS (not the identity: set ``w = 1``).",
)
Pose = message("geometry_msgs/Pose", "Point position\nQuaternion orientation")
PoseStamped = message("geometry_msgs/PoseStamped", "Header header\nPose pose")
Twist = message("geometry_msgs/Twist", "Vector3 linear\nVector3 angular")
Transform = message("geometry_msgs/Transform", "Vector3 translation\nQuaternion rotation")
TransformStamped = message(
    "geometry_msgs/TransformStamped", "Header header\nstring child_frame_id\nTransform transform"
)
Pose2D = message("geometry_msgs/Pose2D", "float64 x\nfloat64 y\nfloat64 theta")
PoseArray = message("geometry_msgs/PoseArray", "Header header\nPose[] poses")

# ----------------------------------------------------------------------------- sensor_msgs, trajectory_msgs

JointState = message(
    "sensor_msgs/JointState",
    "Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\nfloat64[] effort",
)
JointTrajectoryPoint = message(
    "trajectory_msgs/JointTrajectoryPoint",
    "float64[] positions\nfloat64[] velocities\nfloat64[] accelerations\nfloat64[] effort\n"
    "duration time_from_start",
)
JointTrajectory = message(
    "trajectory_msgs/JointTrajectory", "Header header\nstring[] joint_names\nJointTrajectoryPoint[] points"
)
