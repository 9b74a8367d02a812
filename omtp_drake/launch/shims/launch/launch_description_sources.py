"""``PythonLaunchDescriptionSource``: a ``.launch.py`` file's description (the reader loads it)."""

from __future__ import annotations

from typing import Any

from launch.launch_context import LaunchContext, normalize, perform


class PythonLaunchDescriptionSource:
    def __init__(self, launch_file_path: Any) -> None:
        self.launch_file_path = normalize(launch_file_path)

    def get_launch_description(self, context: LaunchContext) -> tuple[str, Any]:
        path = perform(context, self.launch_file_path)
        assert context.load_file is not None
        return path, context.load_file(path)


__all__ = ["PythonLaunchDescriptionSource"]
