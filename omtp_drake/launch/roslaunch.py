"""roslaunch's XML, the part the course's and the students' launch files use.

:func:`read_launch` reads a launch file (with ``ARG:=VALUE`` args) as roslaunch does and
gives what it would start, without starting anything: the parameters it sets (a
:class:`Launch`'s ``params``, by full name) and the nodes it runs (:class:`Node`:
package, type, full name, arguments, remappings, each with the file and line that
declares it). The tags and rules (read in ros_comm's ``roslaunch``):

- ``<arg name default|value [doc]>``: a ``default`` may be set from outside (the
  command line, or the ``<arg>`` of an ``<include>``), a ``value`` may not, an arg with
  neither must be given; an arg given that the file does not declare is an error.
- ``if``/``unless`` on every tag (``true``/``false``/``1``/``0``).
- ``<include file [ns] [pass_all_args]>`` with ``<arg name value>`` children: the
  included file sees only the args passed to it.
- ``<group [ns]>``, ``<remap from to>`` (for the nodes after it in its scope),
  ``<param name value|textfile|command [type]>`` (a command is xacro:
  ``$(find xacro)/xacro [--inorder] FILE [NAME:=VALUE ...]``, run with the PyPI
  ``xacro`` in the workspace), ``<rosparam command="load" file|text [ns] [param]
  [subst_value]>``, ``<node pkg type name [ns] [args]>`` with its own ``param``,
  ``rosparam``, ``remap``; ``<env>`` and ``<machine>`` are read and not used.
- Names: relative names are in the enclosing ``ns``; ``~name`` inside a node is the
  node's private name.

A tag roslaunch does not know (at the top, or inside a ``<node>``) is one warning line
(``Launch.warnings``), as roslaunch warns and goes on.

A MoveIt config's own ``move_group.launch`` (a package with ``config/*.srdf``) is not
read further: its package is the run's MoveIt config (``Launch.moveit_config``).
"""

from __future__ import annotations

import os
import shlex
import xml.etree.ElementTree as ET
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import yaml

from omtp_drake.errors import WorkspaceError
from omtp_drake.launch.substitutions import Context, auto_value, is_true, resolve
from omtp_drake.launch.xml_lines import XmlFile, parse_xml
from omtp_drake.workspace import Workspace, expand_xacro_in

#: libyaml's safe loader where PyYAML has it (the same data as ``yaml.safe_load``, a fifth of
#: the pure-Python parser's time: a course launch loads four rosparam files per read).
_YAML_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

#: Tags that are read and have no effect on the cell.
IGNORED_TAGS = ("env", "machine", "test")


@dataclass(frozen=True)
class Node:
    """A ``<node>`` the launch runs."""

    pkg: str
    type: str
    #: Full name (``/robot1/robot1_spawner``) and namespace (``/robot1``).
    name: str
    namespace: str
    args: str
    remaps: Mapping[str, str]
    #: ``file:line`` of the ``<node>`` tag.
    where: str
    #: A node of a ROS 2 launch file (``launch_ros``' ``Node``: ROS 2's command line).
    ros2: bool = False

    def resolve(self, name: str) -> str:
        """``name`` as this node resolves it (relative names in its namespace)."""
        return join_name(self.namespace, name, private=self.name)


@dataclass
class Launch:
    """What a launch file starts: parameters by full name, nodes, the files read."""

    file: Path
    params: dict[str, Any] = field(default_factory=dict)
    nodes: list[Node] = field(default_factory=list)
    files: list[Path] = field(default_factory=list)
    #: A MoveIt config package whose ``move_group.launch`` the launch includes.
    moveit_config: Path | None = None
    #: What roslaunch warns about and goes on (an unrecognised tag), ``file:line: ...`` each.
    warnings: list[str] = field(default_factory=list)
    #: The ros2_control controllers a (ROS 2) launch's spawners activate, in order.
    controllers: list[str] = field(default_factory=list)


def join_name(namespace: str, name: str, *, private: str = "") -> str:
    """``name`` resolved in ``namespace`` (``~name`` in ``private``), as ROS names resolve."""
    if name.startswith("/"):
        return "/" + name.strip("/")
    if name.startswith("~"):
        return f"{private.rstrip('/')}/{name[1:]}" if private else "/" + name[1:]
    return f"{namespace.rstrip('/')}/{name}".replace("//", "/") if name else namespace


def parse_launch_spec(spec: str) -> tuple[str, str, dict[str, str]]:
    """``'PKG FILE.launch [ARG:=VALUE ...]'`` (``roslaunch``'s words) as (pkg, file, args);
    a first word ending in ``.launch`` is a path (then ``pkg`` is '')."""
    words = shlex.split(spec)
    args: dict[str, str] = {}
    plain = []
    for word in words:
        name, sep, value = word.partition(":=")
        if sep:
            if not name:
                raise WorkspaceError(f"--launch {spec!r}: {word!r} is not NAME:=VALUE")
            args[name] = value
        else:
            plain.append(word)
    if len(plain) == 1 and plain[0].endswith((".launch", ".xml", ".py")):
        return "", plain[0], args
    if len(plain) != 2:
        raise WorkspaceError(
            f"--launch {spec!r}: give 'PKG FILE.launch [ARG:=VALUE ...]' or 'PATH.launch [ARG:=VALUE ...]'"
        )
    return plain[0], plain[1], args


def find_launch_file(workspace: Workspace, pkg: str, file: str) -> Path:
    """The launch file ``file`` of package ``pkg`` (searched in the package, as roslaunch does)."""
    if not pkg:
        path = Path(file).expanduser()
        if not path.is_file():
            raise WorkspaceError(f"--launch: {file}: no such file")
        return path.resolve()
    folder = workspace.package(pkg, needed_by="--launch")
    found = sorted(p for p in folder.rglob(Path(file).name) if p.is_file() and str(p).endswith(file))
    if not found:
        raise WorkspaceError(f"--launch: package {pkg!r} ({folder}) has no launch file {file!r}")
    return found[0]


def read_launch(
    path: Path, args: Mapping[str, str], workspace: Workspace, environ: Mapping[str, str] | None = None
) -> Launch:
    """What the launch file ``path`` run with ``args`` starts (see module doc)."""
    launch = Launch(file=path)
    reader = _Reader(launch, workspace, dict(os.environ if environ is None else environ))
    top = _Scope(namespace="/", remaps={})
    reader.read_file(path, dict(args), top, given_by=f"the command line ({path.name})")
    return launch


@dataclass(frozen=True)
class _Scope:
    namespace: str
    remaps: Mapping[str, str]


class _Reader:
    """Reads launch files into one :class:`Launch` (one reader per launch)."""

    def __init__(self, launch: Launch, workspace: Workspace, environ: dict[str, str]):
        self.launch = launch
        self.workspace = workspace
        self.environ = environ
        #: The files being read (an include of one of them is a loop).
        self.reading: list[Path] = []

    def read_file(self, path: Path, given: dict[str, str], scope: _Scope, given_by: str) -> None:
        if path in self.reading:
            raise WorkspaceError(f"{path}: includes itself (through {given_by})")
        doc = parse_xml(path)
        if doc.root.tag != "launch":
            raise WorkspaceError(f"{path}: not a launch file (its root is <{doc.root.tag}>, not <launch>)")
        self.launch.files.append(path)
        ctx = Context(file=path, args={}, workspace=self.workspace, environ=self.environ)
        used = self._declare_args(doc, ctx, given)
        unused = sorted(set(given) - used)
        if unused:
            raise WorkspaceError(
                f"{path}: unused args [{', '.join(unused)}] given by {given_by}; "
                f"declared: {', '.join(sorted(ctx.args)) or 'none'}"
            )
        self.reading.append(path)
        self._children(doc, doc.root, ctx, scope)
        self.reading.pop()

    def _declare_args(self, doc: XmlFile, ctx: Context, given: dict[str, str]) -> set[str]:
        """Declares the file's top-level and grouped ``<arg>``s in order (they may use each
        other); returns the given args the file declares."""
        used: set[str] = set()
        args: dict[str, str | None] = {}
        ctx.args = args
        for element in _arg_elements(doc, doc.root, ctx):
            ctx.line = doc.line(element)
            name = element.get("name")
            if not name:
                raise ctx.fail("<arg> needs a name")
            if element.get("value") is not None and element.get("default") is not None:
                raise ctx.fail(f"<arg name={name!r}> has both value and default; give one")
            if name in args and name not in given:
                raise ctx.fail(f"<arg name={name!r}> is declared twice")
            if element.get("value") is not None:
                if name in given:
                    raise ctx.fail(f"arg {name!r} has a fixed value in this file and cannot be given")
                args[name] = resolve(element.get("value"), ctx)
            elif name in given:
                used.add(name)
                args[name] = given[name]
            else:
                default = element.get("default")
                args[name] = resolve(default, ctx) if default is not None else None
        ctx.line = None
        return used

    def _children(self, doc: XmlFile, parent: ET.Element, ctx: Context, scope: _Scope) -> None:
        remaps = dict(scope.remaps)
        for element in parent:
            ctx.line = doc.line(element)
            if not _wanted(element, ctx):
                continue
            tag = element.tag
            here = replace(scope, remaps=dict(remaps))
            if tag == "arg":
                continue
            if tag == "group":
                ns = _child_namespace(scope.namespace, element, ctx)
                self._children(doc, element, ctx, _Scope(ns, dict(remaps)))
                ctx.line = doc.line(element)
            elif tag == "include":
                self._include(doc, element, ctx, here)
            elif tag == "remap":
                remaps[resolve(element.get("from"), ctx)] = resolve(element.get("to"), ctx)
            elif tag == "param":
                self._param(element, ctx, scope.namespace, private="")
            elif tag == "rosparam":
                self._rosparam(element, ctx, scope.namespace, private="")
            elif tag == "node":
                self._node(doc, element, ctx, here)
            elif tag not in IGNORED_TAGS:
                # roslaunch's loader: "unrecognized tag", a warning; the launch goes on.
                self.launch.warnings.append(
                    f"{ctx.where()}: unrecognized tag <{tag}>; ignored (launch tags: arg, include, group, "
                    f"remap, param, rosparam, node, {', '.join(IGNORED_TAGS)})"
                )

    def _include(self, doc: XmlFile, element: ET.Element, ctx: Context, scope: _Scope) -> None:
        target = Path(resolve(element.get("file"), ctx))
        where = ctx.where()
        if not target.is_file():
            raise ctx.fail(f"<include file={element.get('file')!r}>: {target} does not exist")
        given = {}
        for child in element:
            if child.tag == "arg" and _wanted(child, ctx):
                ctx.line = doc.line(child)
                if child.get("value") is None:
                    raise ctx.fail(f"<arg name={child.get('name')!r}> of an include needs a value")
                given[child.get("name", "")] = resolve(child.get("value"), ctx)
        if element.get("pass_all_args") and is_true(element.get("pass_all_args"), ctx, "pass_all_args"):
            given = {**{k: v for k, v in ctx.args.items() if v is not None}, **given}
        if _moveit_move_group(target):
            self.launch.moveit_config = target.parent.parent
            self.launch.files.append(target)
            return
        ns = _child_namespace(scope.namespace, element, ctx)
        self.read_file(target.resolve(), given, _Scope(ns, scope.remaps), given_by=f"the include at {where}")

    def _param(self, element: ET.Element, ctx: Context, namespace: str, private: str) -> None:
        name = resolve(element.get("name"), ctx)
        if not name:
            raise ctx.fail("<param> needs a name")
        # Inside a <node>, a relative name is the node's private one (roslaunch's rule).
        full = join_name(private or namespace, name, private=private)
        sources = [k for k in ("value", "textfile", "command", "binfile") if element.get(k) is not None]
        if len(sources) != 1:
            raise ctx.fail(f"<param name={name!r}> needs exactly one of value, textfile, command")
        text = resolve(element.get(sources[0]), ctx)
        if sources[0] == "value":
            value: Any = _typed(text, element.get("type", "auto"), ctx)
        elif sources[0] == "command":
            value = self._command(text, ctx)
        else:
            path = Path(text)
            if not path.is_file():
                raise ctx.fail(f"<param name={name!r} {sources[0]}=...>: {path} does not exist")
            value = path.read_text() if sources[0] == "textfile" else path.read_bytes()
        put_param(self.launch.params, full, value)

    def _command(self, command: str, ctx: Context) -> str:
        """The output of a param's command: xacro only."""
        words = shlex.split(command)
        if not words or Path(words[0]).name not in ("xacro", "xacro.py"):
            raise ctx.fail(
                f"param command {command!r} is not supported; "
                "valid: $(find xacro)/xacro FILE [NAME:=VALUE ...]"
            )
        files = [w for w in words[1:] if ":=" not in w and not w.startswith("-")]
        if len(files) != 1:
            raise ctx.fail(f"xacro command {command!r} must name one file")
        mappings = dict(w.split(":=", 1) for w in words[1:] if ":=" in w)
        path = Path(files[0])
        if not path.is_file():
            raise ctx.fail(f"xacro command: {path} does not exist")
        return expand_xacro_in(self.workspace, path, mappings)

    def _rosparam(self, element: ET.Element, ctx: Context, namespace: str, private: str) -> None:
        command = element.get("command", "load")
        if command != "load":
            raise ctx.fail(f"<rosparam command={command!r}> is not supported; valid: load")
        ns = private or namespace
        if element.get("ns"):
            ns = join_name(namespace, resolve(element.get("ns"), ctx), private=private)
        subst = element.get("subst_value") and is_true(element.get("subst_value"), ctx, "subst_value")
        if element.get("file"):
            path = Path(resolve(element.get("file"), ctx))
            if not path.is_file():
                raise ctx.fail(f"<rosparam file=...>: {path} does not exist")
            text, source = path.read_text(), str(path)
        else:
            text, source = element.text or "", ctx.where()
        if subst:
            text = resolve(text, ctx)
        try:
            data = yaml.load(text, Loader=_YAML_LOADER)  # noqa: S506 (a SafeLoader)
        except yaml.YAMLError as e:
            raise WorkspaceError(f"{source}: malformed YAML ({str(e).splitlines()[0]})") from None
        if element.get("param"):
            put_param(self.launch.params, join_name(ns, resolve(element.get("param"), ctx)), data)
        elif isinstance(data, dict):
            for key, value in data.items():
                put_param(self.launch.params, join_name(ns, str(key)), value)
        elif data is not None:
            raise ctx.fail(f"<rosparam> without param= needs a mapping of names, got {type(data).__name__}")

    def _node(self, doc: XmlFile, element: ET.Element, ctx: Context, scope: _Scope) -> None:
        where = ctx.where()
        pkg, kind = resolve(element.get("pkg"), ctx), resolve(element.get("type"), ctx)
        base = resolve(element.get("name"), ctx)
        if not pkg or not kind or not base:
            raise ctx.fail("<node> needs pkg, type and name")
        ns = _child_namespace(scope.namespace, element, ctx)
        name = join_name(ns, base)
        remaps = dict(scope.remaps)
        for child in element:
            ctx.line = doc.line(child)
            if not _wanted(child, ctx):
                continue
            if child.tag == "remap":
                remaps[resolve(child.get("from"), ctx)] = resolve(child.get("to"), ctx)
            elif child.tag == "param":
                self._param(child, ctx, ns, private=name)
            elif child.tag == "rosparam":
                self._rosparam(child, ctx, ns, private=name)
            elif child.tag not in IGNORED_TAGS:
                # roslaunch: "unrecognized '...' child tag", a warning; the node starts.
                self.launch.warnings.append(
                    f"{ctx.where()}: unrecognized child tag <{child.tag}> of <node>; ignored "
                    "(valid: remap, param, rosparam, env)"
                )
        ctx.line = doc.line(element)
        args = resolve(element.get("args", ""), ctx)
        self.launch.nodes.append(Node(pkg, kind, name, ns, args, remaps, where))


def _arg_elements(doc: XmlFile, parent: ET.Element, ctx: Context) -> Iterator[ET.Element]:
    """The ``<arg>`` tags of the file in order (in groups too) whose if/unless hold, each
    tested when reached (after the args before it are declared)."""
    for element in parent:
        if element.tag not in ("arg", "group"):
            continue
        ctx.line = doc.line(element)
        if not _wanted(element, ctx):
            continue
        if element.tag == "arg":
            yield element
        else:
            yield from _arg_elements(doc, element, ctx)


def _child_namespace(namespace: str, element: ET.Element, ctx: Context) -> str:
    """The namespace inside ``element`` (its ``ns`` in ``namespace``)."""
    if not element.get("ns"):
        return namespace
    return join_name(namespace, resolve(element.get("ns"), ctx))


def _wanted(element: ET.Element, ctx: Context) -> bool:
    if element.get("if") is not None and element.get("unless") is not None:
        raise ctx.fail(f"<{element.tag}> has both if and unless")
    if element.get("if") is not None:
        return is_true(element.get("if"), ctx, "if")
    if element.get("unless") is not None:
        return not is_true(element.get("unless"), ctx, "unless")
    return True


def _typed(text: str, kind: str, ctx: Context) -> Any:
    kind = kind.lower()
    try:
        if kind == "auto":
            return auto_value(text)
        if kind in ("int",):
            return int(text)
        if kind in ("double", "float"):
            return float(text)
        if kind in ("bool", "boolean"):
            if text.strip().lower() not in ("true", "false", "1", "0"):
                raise ValueError(text)
            return text.strip().lower() in ("true", "1")
        if kind in ("str", "string"):
            return text
        if kind == "yaml":
            return yaml.load(text, Loader=_YAML_LOADER)  # noqa: S506 (a SafeLoader)
    except (ValueError, yaml.YAMLError):
        raise ctx.fail(f"param value {text!r} is not a {kind}") from None
    raise ctx.fail(f"param type {kind!r} is unknown; valid: auto, int, double, bool, str, yaml")


def put_param(params: dict[str, Any], name: str, value: Any) -> None:
    """Sets parameter ``name`` (a full name) in the nested ``params``."""
    keys = [k for k in name.split("/") if k]
    node = params
    for key in keys[:-1]:
        child = node.get(key)
        if not isinstance(child, dict):
            child = node[key] = {}
        node = child
    if isinstance(value, dict) and isinstance(node.get(keys[-1]), dict):
        for key, item in value.items():
            put_param(node[keys[-1]], str(key), item)
    else:
        node[keys[-1]] = value


def get_param(params: Mapping[str, Any], name: str) -> Any:
    """The parameter ``name`` (a full name) of the nested ``params``; KeyError if unset."""
    node: Any = params
    for key in (k for k in name.split("/") if k):
        if not isinstance(node, Mapping) or key not in node:
            raise KeyError(name)
        node = node[key]
    return node


def _moveit_move_group(path: Path) -> bool:
    """Is ``path`` a MoveIt config package's own ``move_group.launch`` (its package
    has ``config/*.srdf``)?"""
    return path.name == "move_group.launch" and any((path.parent.parent / "config").glob("*.srdf"))
