"""Documentation that runs (issue 45 item 2): every ``omtp-drake`` command in README.md,
docs/*.md and the READMEs of bench/ and examples/ (fenced and indented blocks, and every
backticked command in the text and tables: the "here" and "run it" columns, and
ros_conformance's "command" column) is collected and run.

Each command's placeholders become real things (:data:`PLACES`): ``$WS`` and ``~/catkin_ws/src``
the course-layout workspace ``tests/fixtures/catkin_ws/src``, ``$T`` the tutorial's robot in
``tests/fixtures/tutorial_ws/src``, ``SCRIPT.py`` and a student's script a stand-in rospy
script, a class folder a folder with that script, ``my_trial.yaml`` the README's own trial.

- **Every** command is parsed by the CLI's own parser and its cell options resolved (the
  launch read, xacro expanded, the typed scenario built): an option the text names that the
  command lacks, a scenario or file that does not exist, fails here.
- **Each distinct command is run once for real**, in this process through ``main``, its first
  documented form shortened where it must be (:data:`SHORTER`), asserting its exit code as the
  text says. Three run for real elsewhere, because a run takes longer than this test's minute:
  ``batch`` and ``grade`` start Dask workers and subprocesses, ``screenshot`` needs a replay
  and Chromium (:data:`REAL_RUN_ELSEWHERE` names the tests, checked to exist). ``bench`` takes
  minutes by design (it is the speed table) and is parse-only everywhere.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

import pytest

from omtp_drake.cli import _values_that_look_like_options, build_parser, main
from omtp_drake.launch.options import resolve_cell_options

ROOT = Path(__file__).resolve().parents[1]
#: What people read: the README, docs/, then the READMEs of bench/ and the examples (their
#: commands too are copied into terminals). README first: a command's first form is the one run.
DOCS = [
    ROOT / "README.md",
    *sorted((ROOT / "docs").glob("*.md")),
    *sorted((ROOT / "bench").rglob("*.md")),
    *sorted((ROOT / "examples").rglob("*.md")),
]
FIXTURES = ROOT / "tests" / "fixtures"
CATKIN = FIXTURES / "catkin_ws" / "src"
TUTORIAL_ROBOT = (
    FIXTURES / "tutorial_ws" / "src" / "slider_arm_description" / "urdf" / "slider_arm.urdf.xacro"
)

#: Placeholder words of the text -> what they stand for here (a word of a command line).
PLACES = {
    "$WS": str(CATKIN),
    "~/catkin_ws/src": str(CATKIN),
    "$A1": "omtp_lecture6 lecture6_assignment1.launch",
    "$T": str(TUTORIAL_ROBOT),
    "slider_arm.urdf.xacro": str(TUTORIAL_ROBOT),
    "SCENARIO": "omtp_factory",
    "BEHAVIOUR NAME": "Conveyor Pick",
    "HTML": "replay.html",
    # docs/ros_control.md's and ros2.md's robots: one with gazebo_ros_control, one with <ros2_control>
    "ROBOT.urdf.xacro": str(
        FIXTURES / "control_ws" / "src" / "two_joint_ros2" / "urdf" / "two_joint.urdf.xacro"
    ),
    "ROBOT": str(FIXTURES / "control_ws" / "src" / "pan_lift_description" / "urdf" / "pan_lift.urdf.xacro"),
    "robot.urdf.xacro": str(TUTORIAL_ROBOT),
    "controllers.yaml": str(
        FIXTURES / "control_ws" / "src" / "pan_lift_description" / "config" / "controllers.yaml"
    ),
}
#: The words a placeholder stands for after an option (``--camera NAME``).
AFTER = {
    "--camera": {"NAME": "logical_camera_1"},
    "--scenario": {"NAME": "lecture6_assignment4", "S": "lecture6_assignment4"},
}
#: tf-echo's ``A B``: two frames.
FRAMES = {"A": "world", "B": "robot1_tool0"}
#: A student's script, as the course's scripts start.
STAND_IN = "import rospy\nrospy.init_node('documented_script')\nrospy.loginfo('a stand-in script ran')\n"
#: How a real run is shortened (extra words), and the exit code the text gives it.
SHORTER = {
    "demo": (["--parts", "1", "-q"], 0),  # `demo` is fill_bin's 10 parts; one shows it works
    "run": (["--parts", "1", "-q"], 0),  # (its scenario's 2 parts: the second adds nothing here)
    "view": (["--timeout", "0.2"], 0),  # the view serves until Stop; 0.2 s shows it came up
    "ros-run": (["--settle-after", "0", "-q"], 0),
    "flexbe-run": (["--timeout", "0.5", "-q"], 1),  # stopped by its --timeout: exit 1, said below
    "ros2": (["--timeout", "0.2"], 0),  # runs until Ctrl-C otherwise
}
#: The commands whose real run lives in another test (see the module doc).
REAL_RUN_ELSEWHERE = {
    "batch": "tests/test_batch.py::test_batch_on_a_dask_scheduler_and_workers",
    "grade": "tests/test_ros_grade.py::test_grade_runs_every_script_and_writes_one_row_each",
    "screenshot": "tests/test_replay_render.py::test_cli_screenshot",
}
PARSE_ONLY = {"bench"}  # minutes by design: the speed table (bench/README.md)
#: The parsed options that make a cell, and the cells resolved so far.
CELL_KEYS = ("launch", "world", "robot", "workspace", "cell_args", "nodes", "sandbox", "cell_file")
RESOLVED: set[tuple[str, ...]] = set()


@dataclass(frozen=True)
class DocCommand:
    where: str  # file:line
    text: str  # as written, after "omtp-drake "

    @property
    def command(self) -> str:
        return self.text.split()[0]


def _blocks(text: str) -> tuple[list[tuple[int, str]], str]:
    """(line number, line) of the fenced and indented blocks' shell lines, and the prose with
    the blocks blanked out (line numbers kept)."""
    lines, prose, fence = [], [], None
    for i, line in enumerate(text.splitlines(), 1):
        if line.startswith("```"):
            fence = None if fence is not None else line[3:].strip()
            prose.append("")
            continue
        if fence is not None and fence in ("bash", "sh", "text", "console", ""):
            lines.append((i, line))
            prose.append("")
        elif fence is None and line.startswith("    ") and not line.lstrip().startswith(("- ", "|")):
            lines.append((i, line.strip()))
            prose.append("")
        else:
            prose.append("" if fence is not None else line)
    return lines, "\n".join(prose)


def collect() -> list[DocCommand]:
    """Every documented command, in file order."""
    found = []
    for path in DOCS:
        name = path.relative_to(ROOT)
        lines, prose = _blocks(path.read_text())
        joined = ""
        for number, line in lines:  # shell lines, with their `\` continuations
            joined = f"{joined} {line.rstrip(chr(92)).strip()}" if joined else line.rstrip(chr(92)).strip()
            if line.endswith("\\"):
                continue
            for part in joined.split(" && "):  # each command of a chain
                match = re.search(r"(?:^\$ |^|\.venv/bin/)omtp-drake (.*)", part)
                if match:
                    text = match.group(1).split("  #")[0].strip()
                    if "$(" in part[: match.start()] and text.endswith(")"):
                        text = text[:-1].strip()  # substituted into another command: $(omtp-drake ...)
                    found.append(DocCommand(f"{name}:{number}", text))
            joined = ""
        for match in re.finditer(r"`omtp-drake ([^`]*)`", prose):
            words = " ".join(match.group(1).split())
            if len(words.split()) > 1 or words == "scenarios":  # not a command's bare name
                found.append(DocCommand(f"{name}:{prose.count(chr(10), 0, match.start()) + 1}", words))
        found += _command_column(name, prose)
    return found


def _command_column(name: Path, prose: str) -> list[DocCommand]:
    """The commands of the tables' "command" columns (docs/ros_conformance.md writes them
    without ``omtp-drake``)."""
    found, column = [], None
    rows = prose.splitlines()
    for number, row in enumerate(rows, 1):
        cells = [c.strip() for c in row.strip().strip("|").split("|")] if row.startswith("|") else []
        if not cells:
            column = None
        elif number < len(rows) and rows[number].startswith("|-"):
            column = cells.index("command") if "command" in cells else None
        elif column is not None and column < len(cells):
            for span in re.findall(r"`((?:ros-run|flexbe-run) [^`]*)`", cells[column]):
                found.append(DocCommand(f"{name}:{number}", span))
    return found


COMMANDS = collect()


@pytest.fixture(scope="module")
def places(tmp_path_factory) -> dict[str, str]:
    """The stand-ins: a script, a class folder holding it, the README's trial."""
    folder = tmp_path_factory.mktemp("docs")
    script = folder / "student_script.py"
    script.write_text(STAND_IN)
    (folder / "class").mkdir()
    (folder / "class" / "student_script.py").write_text(STAND_IN)
    readme = (ROOT / "README.md").read_text()
    trial = re.search(r"```yaml\n(base: lecture6_assignment4\nfaults:.*?)```", readme, re.S)
    assert trial, "README's trial (my_trial.yaml) is gone; update this test"
    (folder / "my_trial.yaml").write_text(trial.group(1))
    return {"script": str(script), "class": str(folder / "class"), "trial": str(folder / "my_trial.yaml")}


def argv_of(doc: DocCommand, places: dict[str, str]) -> list[str]:
    """The command's words with every placeholder replaced (see :data:`PLACES`)."""
    text = doc.text
    for word, value in PLACES.items():
        quoted = shlex.quote(value)
        text = re.sub(rf"(?<![\w/.]){re.escape(word)}(?![\w])", lambda _m, q=quoted: q, text)
        text = text.replace(f'"{quoted}"', quoted)
    words = shlex.split(text)
    out: list[str] = []
    for i, word in enumerate(words):
        previous = out[-1] if out else ""
        if previous in AFTER and word in AFTER[previous]:
            word = AFTER[previous][word]
        elif words[0] == "tf-echo" and word in FRAMES:
            word = FRAMES[word]
        elif word == "my_trial.yaml":
            word = places["trial"]
        elif (word.endswith(".py") or word == "SCRIPT") and previous != "--launch":  # (a ROS 2 launch)
            fixture = list(FIXTURES.rglob(Path(word).name)) if word.endswith(".py") else []
            word = (
                str(ROOT / word)
                if (ROOT / word).is_file()
                else str(fixture[0])
                if fixture
                else places["script"]
            )
        elif words[0] == "grade" and i == 1:
            word = places["class"]
        elif (ROOT / word).exists() and not Path(word).is_absolute() and "/" in word:
            word = str(ROOT / word)
        out.append(word)
    return out


def test_the_docs_hold_the_commands():
    """The collector finds what is there (a collector that finds nothing proves nothing)."""
    names = {c.command for c in COMMANDS}
    assert names >= {"run", "camera", "tf-echo", "frames", "view", "ros-run", "flexbe-run", "grade", "batch"}
    assert names >= {"ros2", "demo", "scenarios", "screenshot"}
    assert len(COMMANDS) >= 50, len(COMMANDS)
    for test in REAL_RUN_ELSEWHERE.values():
        file, _, function = test.partition("::")
        assert (ROOT / file).is_file() and f"def {function}(" in (ROOT / file).read_text(), test


def test_every_markdown_file_outside_the_tests_is_read():
    """A new page of documentation is collected too: every Markdown file of the project's
    folders but tests/ (whose READMEs describe fixtures)."""
    tops = ["omtp_drake", "models", "diagrams", "examples", "notebooks", "bench", "docs"]
    pages = {p for top in tops for p in (ROOT / top).rglob("*.md")}
    assert pages | {ROOT / "README.md"} == set(DOCS), sorted(pages ^ set(DOCS))


@pytest.mark.parametrize("doc", COMMANDS, ids=lambda d: f"{d.where} {d.command}")
def test_every_documented_command_parses_and_resolves_its_cell(doc, places, tmp_path, monkeypatch):
    """The parse and the cell resolution of every documented command (no cell is simulated)."""
    monkeypatch.chdir(tmp_path)
    argv = argv_of(doc, places)
    parser = build_parser()
    try:
        args = parser.parse_args(_values_that_look_like_options(argv))
    except SystemExit as e:
        if "--help" in argv and e.code == 0:
            return
        pytest.fail(f"{doc.where}: `omtp-drake {doc.text}` does not parse (as run: {argv})")
    cell = tuple(str(getattr(args, k, None)) for k in ("scenario", "scenario_option", *CELL_KEYS))
    if cell not in RESOLVED:  # the same cell options are resolved once (the launch read, xacro run)
        resolve_cell_options(args, warn=lambda line: None)
        RESOLVED.add(cell)


def _first_of_each() -> list[DocCommand]:
    firsts: dict[str, DocCommand] = {}
    for doc in COMMANDS:
        firsts.setdefault(doc.command, doc)
    return [d for name, d in firsts.items() if name not in REAL_RUN_ELSEWHERE and name not in PARSE_ONLY]


@pytest.mark.parametrize("doc", _first_of_each(), ids=lambda d: d.command)
def test_each_distinct_command_runs_as_documented(doc, places, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    extra, code = SHORTER.get(doc.command, ([], 0))
    argv = argv_of(doc, places) + extra
    assert main(argv) == code, f"{doc.where}: omtp-drake {' '.join(argv)}\n{capsys.readouterr()}"
    out = capsys.readouterr().out
    if doc.command == "flexbe-run":
        assert "--timeout of 0.5 s simulated time reached" in out, out


@pytest.mark.parametrize("doc", ["README.md", "docs/own_files.md"])
def test_own_files_commands_take_the_options_the_text_lists(doc):
    """ "Your own files" (README's and docs/own_files.md): every command it names takes every
    option it lists."""
    text = (ROOT / doc).read_text()
    section = text[text.index("## Your own files") :]
    section = section[: section.index("\n## ", 5)] if "\n## " in section[5:] else section
    sentence = " ".join(section.split())
    sentence = sentence[sentence.index("Every command that") :]
    named = re.findall(r"`([a-z0-9][a-z0-9-]*)`", sentence[: sentence.index(")")])
    options = re.findall(r"^    (--[a-z]+)", section, re.M)
    assert len(named) >= 10 and {"--launch", "--world", "--robot", "--workspace", "--arg"} <= set(options)
    parsers = build_parser()._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    for command in named:
        flags = {s for a in parsers[command]._actions for s in a.option_strings}
        wanted = set(options) - ({"--scenario"} if command == "view" else set())  # as the text says
        assert wanted <= flags, f"{command} lacks {wanted - flags}"


def test_the_docs_say_one_thing_about_the_tutorial_robot():
    """docs/ros2.md and docs/tutorial_robot.md agree: the ros2 node takes a robot file."""
    ros2 = " ".join((ROOT / "docs" / "ros2.md").read_text().split())
    assert "not loadable here yet" not in ros2
    assert "`--robot [NAME=]FILE[@X,Y,Z[,R,P,Y]]`" in ros2 and "slider_arm.urdf.xacro" in ros2


def _option_mentions() -> list[tuple[str, str, str]]:
    """(file:line, command, option) of every option the text names beside a command:
    backticked spans that start with a command's name (``run SCENARIO [--seed N]``,
    ``grade --moveit melodic``, ``ros-run --latency F``), with or without ``omtp-drake``."""
    commands = set(build_parser()._subparsers._group_actions[0].choices)  # type: ignore[union-attr]
    out = []
    for path in DOCS:
        text = path.read_text()
        for match in re.finditer(r"`(omtp-drake )?([a-z0-9-]+) ([^`]*)`", text):
            if match.group(2) not in commands or (match.group(2) == "ros2" and not match.group(1)):
                continue  # (`ros2 run ...` is ROS 2's own command line)
            where = f"{path.relative_to(ROOT)}:{text.count(chr(10), 0, match.start()) + 1}"
            for option in re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", match.group(3)):
                out.append((where, match.group(2), option))
    return out


def test_every_option_the_text_names_is_the_commands():
    mentions = _option_mentions()
    assert len(mentions) >= 100, len(mentions)
    parsers = build_parser()._subparsers._group_actions[0].choices  # type: ignore[union-attr]
    lacking = [
        f"{where}: {command} {option}"
        for where, command, option in mentions
        if option not in {s for a in parsers[command]._actions for s in a.option_strings}
    ]
    assert not lacking, "the docs name options the commands lack:\n" + "\n".join(lacking)
