"""``/tf`` and ``/gazebo/model_states`` as XCDR1 bytes, packed at once: the bytes Cyclone's
Python serializer writes for the mirrors of :mod:`omtp_drake.ros2.dds_types` (a test
compares them), in a ``struct`` call instead of a walk over dataclasses (20 times faster:
bench/bench_tf.py).

A message's layout depends only on its strings (frame names, model names): each layout is a
``struct.Struct`` made once per list of names, its numbers packed at every message. Encoding:
the 4-byte encapsulation header (XCDR1, little endian), then the fields, each aligned to its
size from the first byte after the header, padding zero.
"""

from __future__ import annotations

import functools
import struct
from collections.abc import Sequence

#: XCDR1 (plain CDR), little endian, no options: what ROS 2's rmw writes first.
HEADER = b"\x00\x01\x00\x00"


class _Layout:
    """A ``struct`` format built field by field, with CDR's alignment."""

    def __init__(self) -> None:
        self.fmt = ["<4s"]
        self.offset = 0  # from the first byte after the header

    def align(self, size: int) -> None:
        pad = -self.offset % size
        if pad:
            self.fmt.append(f"{pad}x")
            self.offset += pad

    def number(self, code: str, size: int, count: int = 1) -> None:
        if count == 0:
            return  # an empty sequence's elements: no alignment either
        self.align(size)
        self.fmt.append(f"{count}{code}")
        self.offset += size * count

    def string(self, text: str) -> bytes:
        """A string field (its length, its bytes and a NUL), fixed in the format."""
        data = text.encode() + b"\x00"
        self.number("I", 4)
        self.fmt.append(f"{len(data)}s")
        self.offset += len(data)
        return data

    def build(self) -> struct.Struct:
        return struct.Struct("".join(self.fmt))


@functools.lru_cache(maxsize=64)
def _tf_layout(frames: tuple[tuple[str, str], ...]) -> tuple[struct.Struct, tuple[bytes, ...]]:
    layout = _Layout()
    layout.number("I", 4)
    strings = []
    for parent, child in frames:
        layout.number("i", 4)
        layout.number("I", 4)
        strings.append(layout.string(parent))
        strings.append(layout.string(child))
        layout.number("d", 8, 7)
    return layout.build(), tuple(strings)


def tf_message(frames: Sequence[tuple[str, str]], numbers: Sequence[Sequence[float]]) -> bytes:
    """A ``tf2_msgs/TFMessage`` of transforms ``frames[i]`` = (parent, child) with
    ``numbers[i]`` = (stamp sec, stamp nanosec, x, y, z, qx, qy, qz, qw)."""
    packer, strings = _tf_layout(tuple(frames))
    values: list[object] = [HEADER, len(frames)]
    for i, n in enumerate(numbers):
        parent, child = strings[2 * i], strings[2 * i + 1]
        values += [int(n[0]), int(n[1]), len(parent), parent, len(child), child, *n[2:]]
    return packer.pack(*values)


@functools.lru_cache(maxsize=16)
def _model_states_layout(names: tuple[str, ...]) -> tuple[struct.Struct, tuple[bytes, ...]]:
    layout = _Layout()
    layout.number("I", 4)
    strings = tuple(layout.string(name) for name in names)
    layout.number("I", 4)
    layout.number("d", 8, 7 * len(names))
    layout.number("I", 4)
    layout.number("d", 8, 6 * len(names))
    return layout.build(), strings


def model_states(
    names: Sequence[str], poses: Sequence[Sequence[float]], twists: Sequence[Sequence[float]]
) -> bytes:
    """A ``gazebo_msgs/ModelStates`` (or ``LinkStates``, the same fields): ``poses[i]`` =
    (x, y, z, qx, qy, qz, qw), ``twists[i]`` = (vx, vy, vz, wx, wy, wz)."""
    packer, strings = _model_states_layout(tuple(names))
    values: list[object] = [HEADER, len(names)]
    for s in strings:
        values += [len(s), s]
    values.append(len(names))
    values += [x for p in poses for x in p]
    values.append(len(names))
    values += [x for w in twists for x in w]
    return packer.pack(*values)
