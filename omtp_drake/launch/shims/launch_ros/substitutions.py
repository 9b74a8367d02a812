"""``FindPackageShare``: a package's share folder, as ament's index finds it."""

from __future__ import annotations

from typing import Any

from ament_index_python.packages import get_package_share_directory
from launch.launch_context import LaunchContext, Substitution, normalize, perform


class FindPackageShare(Substitution):
    def __init__(self, package: Any) -> None:
        self.package = normalize(package)

    def perform(self, context: LaunchContext) -> str:
        return get_package_share_directory(perform(context, self.package))


__all__ = ["FindPackageShare"]
