"""sensor_msgs' image messages: Image, CameraInfo, RegionOfInterest, PointField, PointCloud2.

Field names, types and defaults as genpy generates them for ROS 1 (``uint8[]`` fields
are ``bytes``), and ``sensor_msgs.point_cloud2.read_points``'s job for PointCloud2
(:func:`read_points`).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Iterator, Sequence
from typing import Any, Optional

from omtp_drake.ros.comm.messages import Header, Message


class Image(Message):
    __slots__ = ("header", "height", "width", "encoding", "is_bigendian", "step", "data")
    _type = "sensor_msgs/Image"
    _defaults = (Header, int, int, str, int, int, bytes)


class RegionOfInterest(Message):
    __slots__ = ("x_offset", "y_offset", "height", "width", "do_rectify")
    _type = "sensor_msgs/RegionOfInterest"
    _defaults = (int, int, int, int, bool)


class CameraInfo(Message):
    __slots__ = ("header", "height", "width", "distortion_model", "D", "K", "R", "P", "binning_x",
                 "binning_y", "roi")  # fmt: skip
    _type = "sensor_msgs/CameraInfo"
    _defaults = (Header, int, int, str, list, list, list, list, int, int, RegionOfInterest)


class PointField(Message):
    __slots__ = ("name", "offset", "datatype", "count")
    _type = "sensor_msgs/PointField"
    _defaults = (str, int, int, int)

    INT8, UINT8, INT16, UINT16, INT32, UINT32, FLOAT32, FLOAT64 = 1, 2, 3, 4, 5, 6, 7, 8


class PointCloud2(Message):
    __slots__ = ("header", "height", "width", "fields", "is_bigendian", "point_step", "row_step", "data",
                 "is_dense")  # fmt: skip
    _type = "sensor_msgs/PointCloud2"
    _defaults = (Header, int, int, list, bool, int, int, bytes, bool)


#: struct codes of PointField datatypes.
_CODES = {1: "b", 2: "B", 3: "h", 4: "H", 5: "i", 6: "I", 7: "f", 8: "d"}


def read_points(
    cloud: PointCloud2,
    field_names: Optional[Sequence[str]] = None,
    skip_nans: bool = False,
    uvs: Sequence[tuple[int, int]] = (),
) -> Iterator[tuple[Any, ...]]:
    """``sensor_msgs.point_cloud2.read_points``: the points of ``cloud`` as tuples of the
    named fields (all by default), skipping those with a NaN with ``skip_nans``; only the
    (u, v) pixels ``uvs`` when given."""
    fields = {f.name: f for f in cloud.fields}
    names = list(field_names) if field_names else [f.name for f in cloud.fields]
    for name in names:
        if name not in fields:
            raise ValueError(f"PointCloud2 has no field {name!r}; fields: {', '.join(fields)}")
    order = ">" if cloud.is_bigendian else "<"
    parts = [(fields[n].offset, order + _CODES[fields[n].datatype]) for n in names]
    data = cloud.data
    pixels = uvs or [(u, v) for v in range(cloud.height) for u in range(cloud.width)]
    for u, v in pixels:
        start = v * cloud.row_step + u * cloud.point_step
        point = tuple(struct.unpack_from(code, data, start + offset)[0] for offset, code in parts)
        if skip_nans and any(isinstance(x, float) and math.isnan(x) for x in point):
            continue
        yield point
