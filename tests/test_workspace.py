"""A student's workspace: packages and Gazebo models found as rospack and Gazebo find them,
and xacro's ``$(find PKG)`` resolved in it. Fixtures are written here, in a catkin layout."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from omtp_drake.errors import MissingPackageError, WorkspaceError
from omtp_drake.workspace import Workspace, expand_xacro_in


def _package(folder: Path, name: str, export: str = "") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(
        f'<?xml version="1.0"?>\n<package format="2">\n  <name>{name}</name>\n  <version>0.0.1</version>\n'
        f"  <export>{export}</export>\n</package>\n"
    )
    return folder


@pytest.fixture
def catkin_src(tmp_path: Path) -> Path:
    src = tmp_path / "catkin_ws" / "src"
    support = _package(src / "omtp_course" / "omtp_support", "omtp_support")
    (support / "urdf").mkdir()
    (support / "urdf" / "box.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="box">\n'
        '  <xacro:arg name="size" default="0.5"/>\n'
        '  <xacro:include filename="$(find omtp_support)/urdf/link.xacro"/>\n'
        '  <xacro:box_link name="base" size="$(arg size)"/>\n</robot>\n'
    )
    (support / "urdf" / "link.xacro").write_text(
        '<?xml version="1.0"?>\n<robot xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:macro name="box_link" params="name size">\n'
        '    <link name="${name}"><visual><geometry><box size="${size} ${size} ${size}"/></geometry>'
        "</visual></link>\n  </xacro:macro>\n</robot>\n"
    )
    (support / "nested").mkdir()
    _package(support / "nested" / "inner", "inner_pkg")  # inside a package: not a package of its own
    gazebo = _package(
        src / "omtp_course" / "omtp_gazebo",
        "omtp_gazebo",
        export='<gazebo_ros gazebo_model_path="${prefix}/models"/>',
    )
    camera = gazebo / "models" / "logical_camera1"
    camera.mkdir(parents=True)
    (camera / "model.config").write_text("<model><name>logical_camera1</name><sdf>model.sdf</sdf></model>")
    (camera / "model.sdf").write_text('<sdf version="1.6"><model name="logical_camera1"/></sdf>')
    ignored = _package(src / "old_attempt", "omtp_old")
    (ignored / "CATKIN_IGNORE").write_text("")
    return src


def test_packages_are_found_as_rospack_finds_them(catkin_src: Path):
    ws = Workspace.from_dirs([catkin_src], environ={})
    assert set(ws.packages) == {"omtp_support", "omtp_gazebo"}
    assert ws.package("omtp_support", needed_by="x") == catkin_src / "omtp_course" / "omtp_support"


def test_exported_gazebo_models_resolve_by_model_uri(catkin_src: Path):
    ws = Workspace.from_dirs([catkin_src], environ={})
    path = ws.resolve("model://logical_camera1/model.sdf", needed_by="world.world")
    assert path.read_text().startswith("<sdf")
    assert "logical_camera1" in ws.package_map().GetPackageNames()


def test_the_first_folder_wins_and_ros_package_path_comes_after(catkin_src: Path, tmp_path: Path):
    other = _package(tmp_path / "other" / "omtp_support", "omtp_support")
    extra = _package(tmp_path / "extra" / "ur_description", "ur_description")
    env = {"ROS_PACKAGE_PATH": f"{other.parent}:{extra.parent}"}
    ws = Workspace.from_dirs([catkin_src], environ=env)
    assert ws.packages["omtp_support"] == catkin_src / "omtp_course" / "omtp_support"
    assert ws.packages["ur_description"] == extra


def test_a_missing_package_names_itself_the_file_and_the_flag(catkin_src: Path):
    ws = Workspace.from_dirs([catkin_src], environ={})
    with pytest.raises(MissingPackageError) as e:
        ws.resolve("package://ur_description/meshes/ur10/visual/base.dae", needed_by="/ws/factory.xacro")
    message = str(e.value)
    assert "/ws/factory.xacro" in message and "'ur_description'" in message and "--workspace" in message


def test_a_workspace_that_is_not_a_folder_is_refused(tmp_path: Path):
    with pytest.raises(WorkspaceError, match="not a folder"):
        Workspace.from_dirs([tmp_path / "nope"], environ={})


def test_xacro_find_resolves_in_the_workspace(catkin_src: Path):
    ws = Workspace.from_dirs([catkin_src], environ={})
    urdf = expand_xacro_in(
        ws, catkin_src / "omtp_course" / "omtp_support" / "urdf" / "box.xacro", {"size": "0.2"}
    )
    assert '<box size="0.2 0.2 0.2"/>' in urdf


def test_xacro_with_a_missing_package_names_the_package_and_the_file(catkin_src: Path, tmp_path: Path):
    bad = tmp_path / "bad.xacro"
    bad.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="b">'
        '<xacro:include filename="$(find ur_description)/urdf/ur10.urdf.xacro"/></robot>'
    )
    ws = Workspace.from_dirs([catkin_src], environ={})
    with pytest.raises(MissingPackageError, match="'ur_description' not found"):
        expand_xacro_in(ws, bad)


def test_xacro_arg_without_a_value_says_how_to_give_it(tmp_path: Path):
    bad = tmp_path / "arg.xacro"
    bad.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="b"><link name="$(arg prefix)base"/></robot>'
    )
    with pytest.raises(
        WorkspaceError, match=r"arg\.xacro: \$\(arg prefix\) has no value; give it as prefix:=VALUE"
    ):
        expand_xacro_in(Workspace(), bad)


def test_a_malformed_xacro_names_the_file(tmp_path: Path):
    bad = tmp_path / "broken.urdf.xacro"
    bad.write_text('<robot name="b"><link name="a"></robot>')
    with pytest.raises(WorkspaceError, match=r"broken\.urdf\.xacro: not well-formed XML"):
        expand_xacro_in(Workspace(), bad)


def test_find_goes_through_an_ament_prefix_built_once_per_workspace(catkin_src: Path, monkeypatch):
    from omtp_drake.workspace.xacro_files import ament_prefix

    monkeypatch.setenv("AMENT_PREFIX_PATH", "/opt/ros/elsewhere")
    ws = Workspace.from_dirs([catkin_src], environ={})
    prefix = ament_prefix(ws)
    assert ament_prefix(Workspace.from_dirs([catkin_src], environ={})) == prefix
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    assert sorted(p.name for p in index.iterdir()) == sorted(ws.packages)
    assert (prefix / "share" / "omtp_support").resolve() == ws.packages["omtp_support"].resolve()
    expand_xacro_in(ws, catkin_src / "omtp_course" / "omtp_support" / "urdf" / "box.xacro")
    assert os.environ["AMENT_PREFIX_PATH"] == "/opt/ros/elsewhere"


def test_no_name_of_the_xacro_package_is_assigned_in_omtp_drake():
    """xacro is used as published: no module of omtp_drake assigns to an attribute or an
    item of anything imported from xacro (``xacro.x = ...``, ``substitution_args._eval_dict[k] = ...``)."""
    import ast

    package = Path(__file__).resolve().parents[1] / "omtp_drake"
    wrong = []
    for path in sorted(package.rglob("*.py")):
        tree = ast.parse(path.read_text())
        names = {a.asname or a.name.split(".")[0] for n in ast.walk(tree) if isinstance(n, ast.Import)
                 for a in n.names if a.name.split(".")[0] == "xacro"}  # fmt: skip
        names |= {a.asname or a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)
                  and (n.module or "").split(".")[0] == "xacro" for a in n.names}  # fmt: skip
        for node in ast.walk(tree):
            targets = node.targets if isinstance(node, ast.Assign) else []
            targets += [node.target] if isinstance(node, (ast.AugAssign, ast.AnnAssign)) else []
            for target in targets:
                for element in ast.walk(target):
                    root = element
                    while isinstance(root, (ast.Attribute, ast.Subscript)):
                        root = root.value
                    if root is not element and isinstance(root, ast.Name) and root.id in names:
                        wrong.append(f"{path.relative_to(package)}:{node.lineno}")
            if isinstance(node, ast.Call) and getattr(node.func, "id", "") == "setattr" and node.args:
                if isinstance(node.args[0], ast.Name) and node.args[0].id in names:
                    wrong.append(f"{path.relative_to(package)}:{node.lineno}")
    assert not wrong, wrong


def test_a_find_result_in_the_description_names_the_package_folder(catkin_src: Path, tmp_path: Path):
    robot = tmp_path / "r.urdf.xacro"
    robot.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="r"><link name="l"><visual><geometry>'
        '<mesh filename="file://$(find omtp_support)/meshes/m.stl"/></geometry></visual></link></robot>'
    )
    urdf = expand_xacro_in(Workspace.from_dirs([catkin_src], environ={}), robot)
    folder = (catkin_src / "omtp_course" / "omtp_support").resolve()
    assert f'filename="file://{folder}/meshes/m.stl"' in urdf


def test_an_expansion_is_reused_until_a_file_it_read_changes(catkin_src: Path, monkeypatch):
    import xacro

    ws = Workspace.from_dirs([catkin_src], environ={})
    box = catkin_src / "omtp_course" / "omtp_support" / "urdf" / "box.xacro"
    first = expand_xacro_in(ws, box, {"size": "0.25"})
    calls = []
    process_file = xacro.process_file
    monkeypatch.setattr(xacro, "process_file", lambda *a, **k: calls.append(a) or process_file(*a, **k))
    assert expand_xacro_in(ws, box, {"size": "0.25"}) == first and not calls  # the same files: reused
    assert 'size="0.3 0.3 0.3"' in expand_xacro_in(ws, box, {"size": "0.3"}) and len(calls) == 1
    link = catkin_src / "omtp_course" / "omtp_support" / "urdf" / "link.xacro"
    link.write_text(link.read_text().replace("<visual>", '<visual name="v">'))  # an included file edited
    assert '<visual name="v">' in expand_xacro_in(ws, box, {"size": "0.25"}) and len(calls) == 2
    env = catkin_src / "omtp_course" / "omtp_support" / "urdf" / "env.xacro"
    env.write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="e">'
        '<link name="$(optenv LINK base)"/></robot>'
    )
    expand_xacro_in(ws, env)
    monkeypatch.setenv("LINK", "other")
    assert '<link name="other"/>' in expand_xacro_in(ws, env) and len(calls) == 4  # reads the environment
