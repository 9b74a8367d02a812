"""``LaunchDescription``: the entities a launch file's ``generate_launch_description()`` returns."""

from __future__ import annotations

from collections.abc import Iterable

from launch.launch_context import LaunchContext, LaunchDescriptionEntity


class LaunchDescription(LaunchDescriptionEntity):
    def __init__(
        self,
        initial_entities: Iterable[LaunchDescriptionEntity] | None = None,
        *,
        deprecated_reason: str | None = None,
    ) -> None:
        self.entities = list(initial_entities or [])

    def add_action(self, action: LaunchDescriptionEntity) -> None:
        self.entities.append(action)

    add_entity = add_action

    def visit(self, context: LaunchContext) -> list[LaunchDescriptionEntity]:
        return self.entities

    def get_launch_arguments(self) -> list:
        from launch.actions import DeclareLaunchArgument

        return [e for e in self.entities if isinstance(e, DeclareLaunchArgument)]
