"""A ROS 2 bag as one MCAP file: what ``ros2 bag play`` (rosbag2's MCAP storage) and
Foxglove open (``--bag run.mcap``; the ``mcap`` and ``mcap-ros2-support`` wheels of the
``ros2`` extra).

Each topic is a channel of message encoding ``cdr`` whose schema is its type
(``pkg/msg/Name``, encoding ``ros2msg``, the concatenated definition of
:mod:`omtp_drake.ros.bag.definitions`). A message comes as CDR bytes (a transport's
serialization) or as a value (a dict, or an object with the fields) serialized here from
the definition. Times are simulated: a message's log time is when the run published it
and its publish time is its stamp (the header's, else the log time), in nanoseconds from
the run's start.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any, Optional

from omtp_drake.errors import ConfigError, MissingExtraError

#: What installs the bag writer: the project's extra.
INSTALL_HINT = 'pip install -e ".[ros2]"'


def _ns(t: float) -> int:
    if not (math.isfinite(t) and t >= 0):
        raise ConfigError(f"a bag's times are simulated seconds >= 0, got {t!r}")
    return int(round(t * 1e9))


class Ros2Bag:
    """An MCAP file at ``path`` being written (:meth:`close` finishes it; a context manager)."""

    def __init__(self, path: str | Path):
        try:
            from mcap.writer import CompressionType, Writer
            from mcap_ros2._dynamic import serialize_dynamic
        except ImportError as e:
            raise MissingExtraError(
                f"--bag needs the mcap wheels ({e}); install the project's ros2 extra: {INSTALL_HINT}"
            ) from None
        self.path = Path(path)
        if self.path.suffix != ".mcap":
            raise ConfigError(f"--bag {str(path)!r}: a bag is an MCAP file; valid: a name ending in .mcap")
        self._serialize_dynamic = serialize_dynamic
        self._file = self.path.open("wb")
        self._writer = Writer(self._file, compression=CompressionType.ZSTD)
        self._writer.start(profile="ros2", library="omtp_drake")
        #: type -> (schema id, its encoder or None before a value needs one)
        self._schemas: dict[str, int] = {}
        self._encoders: dict[str, Callable[[Any], bytes]] = {}
        self._texts: dict[str, str] = {}
        #: (topic, type) -> channel id; topic -> messages written
        self._channels: dict[tuple[str, str], int] = {}
        self.counts: dict[str, int] = {}
        self._closed = False

    def has_type(self, type_name: str) -> bool:
        return type_name in self._schemas

    def add_type(self, type_name: str, definition: str) -> None:
        """Registers ``type_name`` (``pkg/msg/Name``) with its concatenated definition."""
        if type_name not in self._schemas:
            self._schemas[type_name] = self._writer.register_schema(type_name, "ros2msg", definition.encode())
            self._texts[type_name] = definition

    def _channel(self, topic: str, type_name: str, qos: str) -> int:
        key = (topic, type_name)
        if key not in self._channels:
            if type_name not in self._schemas:
                raise ConfigError(f"{topic}: type {type_name} was not added to the bag")
            metadata = {"offered_qos_profiles": qos} if qos else {}
            self._channels[key] = self._writer.register_channel(
                topic, "cdr", self._schemas[type_name], metadata
            )
        return self._channels[key]

    def write_cdr(
        self,
        topic: str,
        type_name: str,
        data: bytes,
        time: float,
        stamp: Optional[float] = None,
        qos: str = "",
    ) -> None:
        """One message of ``topic`` as CDR bytes (with their encapsulation header)."""
        channel = self._channel(topic, type_name, qos)
        count = self.counts.get(topic, 0)
        self.counts[topic] = count + 1
        log = _ns(time)
        self._writer.add_message(
            channel,
            log_time=log,
            data=data,
            publish_time=log if stamp is None else _ns(stamp),
            sequence=count,
        )

    def write(
        self,
        topic: str,
        type_name: str,
        value: Any,
        time: float,
        stamp: Optional[float] = None,
        qos: str = "",
    ) -> None:
        """One message of ``topic`` as a value, serialized from its type's definition."""
        encoder = self._encoders.get(type_name)
        if encoder is None:
            encoder = self._serialize_dynamic(type_name, self._texts[type_name])[type_name]
            self._encoders[type_name] = encoder
        self.write_cdr(topic, type_name, encoder(value), time, stamp, qos)

    def close(self) -> None:
        """Finishes the file (its index and summary): from then on readers open it."""
        if not self._closed:
            self._closed = True
            self._writer.finish()
            self._file.close()

    def __enter__(self) -> Ros2Bag:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()
