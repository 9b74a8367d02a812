"""``python -m omtp_drake.ros2.interface_generate PACKAGE DEFINITIONS GEN PYTHON``: the
rosidl generation step of :mod:`omtp_drake.ros2.interface_build`, in its own process (the
generators need ``AMENT_PREFIX_PATH`` and print as they go).

The ``.msg``/``.srv``/``.action`` files become ``.idl`` (``rosidl_adapter``'s converters;
its command line needs ``catkin_pkg``, which the wheels lack), then each generator writes
into ``GEN/<part>/PACKAGE`` as the ``rosidl_generate_interfaces`` CMake function lays them
out, and the Python generator into ``PYTHON``. The generators are called directly, not
through ``rosidl generate``: two distributions of each register the same entry points and
the command stops on the duplicate.
"""

from __future__ import annotations

import sys
from pathlib import Path


def generate(package: str, definitions: Path, gen: Path, python: Path) -> None:
    from rosidl_adapter.action import convert_action_to_idl
    from rosidl_adapter.msg import convert_msg_to_idl
    from rosidl_adapter.srv import convert_srv_to_idl
    from rosidl_generator_c.cli import GenerateC
    from rosidl_generator_py.cli import GeneratePython
    from rosidl_typesupport_c.cli import GenerateCTypesupport
    from rosidl_typesupport_fastrtps_c.cli import GenerateFastRTPSCTypesupport
    from rosidl_typesupport_introspection_c.cli import GenerateIntrospectionCTypesupport

    converters = {".msg": convert_msg_to_idl, ".srv": convert_srv_to_idl, ".action": convert_action_to_idl}
    idl_root = gen / "idl"
    files = []
    for path in sorted(definitions.rglob("*")):
        if path.suffix in converters:
            relative = path.relative_to(definitions)
            idl = converters[path.suffix](definitions, package, relative, idl_root / relative.parent)
            files.append(f"{idl_root}:{idl.relative_to(idl_root)}")
    includes = [str(Path(sys.prefix) / "share")]
    supports = ["rosidl_typesupport_c", "rosidl_typesupport_fastrtps_c", "rosidl_typesupport_introspection_c"]
    generators = [
        ("c", GenerateC("c")),
        ("typesupport_c", GenerateCTypesupport("typesupport_c", typesupport_implementations=supports[1:])),
        ("rosidl_typesupport_fastrtps_c", GenerateFastRTPSCTypesupport("fastrtps_c")),
        ("rosidl_typesupport_introspection_c", GenerateIntrospectionCTypesupport("introspection_c")),
    ]
    for part, generator in generators:
        generator.generate(package, files, includes, output_path=gen / part / package)
    GeneratePython("py", typesupport_implementations=supports).generate(
        package, files, includes, output_path=python
    )


if __name__ == "__main__":
    package, definitions, gen, python = sys.argv[1:5]
    generate(package, Path(definitions), Path(gen), Path(python))
