"""sensor_msgs' image messages: Image, CameraInfo, RegionOfInterest, PointField, PointCloud2.

Declared from their ``.msg`` text (:mod:`omtp_drake.ros.comm.messages`'s factory): field
names, types and defaults as genpy generates them for ROS 1 (``uint8[]`` fields are
``bytes``), and ``sensor_msgs.point_cloud2.read_points``'s job for PointCloud2
(:func:`read_points`).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Iterator, Sequence
from typing import Any, Optional

from omtp_drake.ros.comm.messages import message

Image = message(
    "sensor_msgs/Image",
    "Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\n"
    "uint8[] data",
)
RegionOfInterest = message(
    "sensor_msgs/RegionOfInterest",
    "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify",
)
CameraInfo = message(
    "sensor_msgs/CameraInfo",
    # The fixed-size K, R and P are empty lists until set (as the variable-size D).
    """
    Header header
    uint32 height
    uint32 width
    string distortion_model
    float64[] D
    float64[9] K
    float64[9] R
    float64[12] P
    uint32 binning_x
    uint32 binning_y
    RegionOfInterest roi
    """,
)
PointField = message(
    "sensor_msgs/PointField",
    """
    string name
    uint32 offset
    uint8 datatype
    uint32 count
    uint8 INT8=1
    uint8 UINT8=2
    uint8 INT16=3
    uint8 UINT16=4
    uint8 INT32=5
    uint8 UINT32=6
    uint8 FLOAT32=7
    uint8 FLOAT64=8
    """,
)
PointCloud2 = message(
    "sensor_msgs/PointCloud2",
    """
    Header header
    uint32 height
    uint32 width
    PointField[] fields
    bool is_bigendian
    uint32 point_step
    uint32 row_step
    uint8[] data
    bool is_dense
    """,
)


#: struct codes of PointField datatypes.
_CODES = {1: "b", 2: "B", 3: "h", 4: "H", 5: "i", 6: "I", 7: "f", 8: "d"}


def read_points(
    cloud: Any,
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
