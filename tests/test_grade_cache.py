"""``grade`` in a fresh model cache: the simulator's own files (converted meshes, the mesh
memo, stand-ins) are made before the runs and are no refusal of a student's; what a
script itself writes outside its folder still is."""

import csv
import os
import shutil
import tempfile
import textwrap
from pathlib import Path

import pytest

from omtp_drake.grading.grade import grade_folder
from omtp_drake.grading.isolation import bwrap_works

SCENARIO = "lecture6_assignment3"
SANDBOX = "bwrap" if bwrap_works() else "none"

#: A class as students write it: rospy and tf2, moveit_commander (ROS Melodic's), and one
#: who keeps notes in the model cache it found in the environment.
CLASS = {
    "find_part.py": """
        #!/usr/bin/env python
        import rospy
        import tf2_ros

        rospy.init_node("find_part")
        buf = tf2_ros.Buffer()
        listener = tf2_ros.TransformListener(buf)
        rospy.sleep(0.5)
        t = buf.lookup_transform("world", "vacuum_gripper2_suction_cup", rospy.Time(0), rospy.Duration(1.0))
        print("cup at %.3f %.3f %.3f" % (t.transform.translation.x, t.transform.translation.y,
                                         t.transform.translation.z))
        """,
    "move_home.py": (Path(__file__).parent / "fixtures" / "grade_class" / "move_home.py").read_text(),
    "notes_in_cache.py": """
        #!/usr/bin/env python
        import glob
        import os
        import rospy

        rospy.init_node("notes")
        cache = glob.glob(os.path.join(os.environ["OMTP_DRAKE_CACHE"], "models-*"))[0]
        with open(os.path.join(cache, "notes.txt"), "w") as f:
            f.write("mine")
        """,
}


@pytest.fixture(scope="module")
def graded(tmp_path_factory):
    """The class graded in a fresh model cache: (the CSV's rows by script, the cache's root,
    the results folder). The cache is where a user's is, under ~/.cache: bubblewrap's
    private /tmp would hide one under /tmp, and the guard lets a run write in /tmp."""
    tmp = tmp_path_factory.mktemp("grade_cache")
    home_cache = Path.home() / ".cache"
    home_cache.mkdir(parents=True, exist_ok=True)
    cache = Path(tempfile.mkdtemp(prefix="omtp_drake_test_", dir=home_cache))
    try:
        yield _grade_class(tmp, cache)
    finally:
        shutil.rmtree(cache, ignore_errors=True)


def _grade_class(tmp: Path, cache: Path) -> tuple[dict, Path, Path]:
    """The class written to ``tmp/class`` and graded with the model cache at ``cache``."""
    folder = tmp / "class"
    folder.mkdir()
    for name, text in CLASS.items():
        (folder / name).write_text(textwrap.dedent(text).lstrip())
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("OMTP_DRAKE_CACHE", str(cache))
        grade_folder(
            folder, SCENARIO, workers=2, timeout=2.0, out=tmp / "out", sandbox=SANDBOX,
            options={"moveit": "melodic"},
        )  # fmt: skip
    rows = {r["script"]: r for r in csv.DictReader(open(tmp / "out" / "grades.csv"))}
    return rows, cache, tmp / "out"


def test_no_row_holds_the_simulators_own_files(graded):
    rows, cache, out = graded
    assert rows["find_part.py"]["status"] == "ok" and rows["move_home.py"]["status"] == "ok"
    assert "cup at " in (out / "runs" / "find_part.stdout.txt").read_text()
    assert "joints [" in (out / "runs" / "move_home.stdout.txt").read_text()
    for name in ("find_part.py", "move_home.py"):
        assert rows[name]["refused"] == "" and str(cache) not in ",".join(rows[name].values())
    # What the grader made before the runs: the arms, their meshes, the mesh memo.
    (models,) = cache.glob("models-*")
    assert {"meshes", "mesh_facts"} <= {p.name for p in models.iterdir()}
    assert len(list(models.glob("*_ur5_*.urdf"))) and len(list(models.glob("*_ur10_*.urdf")))


def test_a_script_that_writes_into_the_cache_is_refused(graded):
    rows, cache, _ = graded
    (models,) = cache.glob("models-*")
    row = rows["notes_in_cache.py"]
    assert row["status"] == "exception"
    # The guard refuses it (no sandbox) or the kernel does (bubblewrap: read-only).
    assert row["refused"].startswith(f"write to {models / 'notes.txt'} (")
    assert not (models / "notes.txt").exists()


def test_a_run_with_a_read_only_cache_writes_only_to_its_own_layer(graded, tmp_path, monkeypatch):
    """What the cache lacks goes to the run's layer; what it holds is read, nothing written."""
    from omtp_drake.assets import CACHE_LAYER_ENV, cache_entry

    _, cache, _ = graded
    (models,) = cache.glob("models-*")
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(cache))
    monkeypatch.setenv(CACHE_LAYER_ENV, str(tmp_path / "layer"))
    before = sorted(os.path.relpath(p, models) for p in models.rglob("*"))
    held = next(models.glob("*.urdf"))
    assert cache_entry(held.name) == held
    missing = cache_entry("mesh_facts/not-yet.pickle")
    assert missing == tmp_path / "layer" / models.name / "mesh_facts" / "not-yet.pickle"
    assert missing.parent.is_dir() and sorted(os.path.relpath(p, models) for p in models.rglob("*")) == before
    assert Path(held).read_text().count(str(models / "meshes")) > 0  # its meshes: the cache's
