"""Fuzz of the world/launch loader: mutated Gazebo worlds, model SDFs, launch files and URDFs.

Each case copies ``tests/fixtures/world_ws`` (a table-and-cube world, a model included by
``model://``, a launch that spawns a URDF shelf and a box), mutates one of its files once
(a number made NaN, negative, huge or a word; a line deleted or doubled; the file cut
short; a tag renamed; an attribute dropped; a stray element; a link reference renamed),
loads it as the commands do (``own_cell``; then the loaded models in a bare plant with
Drake's parser) and sorts the outcome: loaded, or refused with one ``OmtpError`` line
naming the file; anything else (another exception, a message of several lines, one
that names no file) is a finding, printed with its case. Seeded: the same cases on every
machine.

    python bench/bench_world_fuzz.py [--cases 300] [--seed 0] [--show loaded|refused]
"""

import argparse
import random
import re
import shutil
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
WS = ROOT / "tests" / "fixtures" / "world_ws" / "src"
#: (file mutated, how it is loaded: "world" or "launch").
TARGETS = [
    ("my_cell/worlds/table_cube.world", "world"),
    ("my_cell/models/work_table/model.sdf", "world"),
    ("my_cell/launch/shelf.launch", "launch"),
    ("my_cell/urdf/box.urdf", "launch"),
    ("my_cell/urdf/shelf.urdf.xacro", "launch"),
]
NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d+)?(?![\w.])")


def mutate(text: str, rng: random.Random) -> tuple[str, str]:
    """One random mutation of ``text`` and what it was."""
    lines = text.splitlines(keepends=True)
    kind = rng.choice(["number", "number", "delete", "double", "cut", "tag", "attribute", "stray", "name"])
    if kind == "number":
        found = list(NUMBER.finditer(text))
        if found:
            m = rng.choice(found)
            value = rng.choice(["nan", "inf", "-1", "0", "1e9", "abc", ""])
            return text[: m.start()] + value + text[m.end() :], f"number {m.group()!r} -> {value!r}"
    if kind == "delete" and len(lines) > 2:
        i = rng.randrange(1, len(lines))
        return "".join(lines[:i] + lines[i + 1 :]), f"line {i + 1} deleted"
    if kind == "double":
        i = rng.randrange(len(lines))
        return "".join(lines[: i + 1] + lines[i:]), f"line {i + 1} doubled"
    if kind == "cut":
        n = rng.randrange(len(text))
        return text[:n], f"cut at {n}"
    tags = re.findall(r"<([A-Za-z_][\w:]*)", text)
    if kind == "tag" and tags:
        tag = rng.choice(tags)
        return text.replace(f"<{tag}", f"<{tag}x", 1).replace(f"</{tag}>", f"</{tag}x>", 1), f"tag {tag} renamed"
    attributes = re.findall(r'\s([\w:]+="[^"]*")', text)
    if kind == "attribute" and attributes:
        attribute = rng.choice(attributes)
        return text.replace(" " + attribute, "", 1), f"attribute {attribute} dropped"
    names = re.findall(r'(?:name|reference|link)="([^"$]+)"', text)
    if kind == "name" and names:
        name = rng.choice(names)
        return text.replace(f'"{name}"', f'"{name}_typo"', 1), f"name {name} renamed"
    i = rng.randrange(1, max(2, len(lines)))
    stray = rng.choice(['<xacro:thing a="1"/>\n', '<joint name="j" type="fixed"/>\n', "<frobnicate/>\n"])
    return "".join(lines[:i] + [stray] + lines[i:]), f"stray {stray.strip()} at line {i + 1}"


def load(src: Path, how: str) -> None:
    """Loads the workspace ``src`` as the commands do (and its models with Drake's parser)."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    from omtp_drake.cell.described_models import add_described_models
    from omtp_drake.launch import own_cell

    if how == "world":
        cell = own_cell(world=src / TARGETS[0][0], workspace=[src], environ={})
    else:
        cell = own_cell("my_cell shelf.launch", workspace=[src], environ={})
    plant = MultibodyPlant(0.01)
    add_described_models(Parser(plant), cell.scenario.models)
    plant.Finalize()


def run_case(case: int, seed: int, folder: Path) -> tuple[str, str]:
    """(outcome, detail) of case ``case``: ``loaded``, ``refused`` or ``FINDING``."""
    from omtp_drake.errors import OmtpError

    rng = random.Random(seed * 100_003 + case)
    file, how = rng.choice(TARGETS)
    src = folder / f"case{case}" / "src"
    shutil.copytree(WS, src)
    text, what = mutate((src / file).read_text(), rng)
    (src / file).write_text(text)
    label = f"case {case}: {file}: {what}"
    try:
        load(src, how)
    except OmtpError as e:
        message = str(e)
        if "\n" in message or str(src) not in message:
            return "FINDING", f"{label}: {type(e).__name__} not one line naming the file: {message!r}"
        return "refused", f"{label}: {message}"
    except Exception as e:  # noqa: BLE001 (the finding)
        lines = traceback.format_exception_only(type(e), e)
        return "FINDING", f"{label}: {type(e).__name__}: {''.join(lines).strip()[:400]}"
    finally:
        shutil.rmtree(src.parent, ignore_errors=True)
    return "loaded", label


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=300)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--show", choices=["loaded", "refused"], help="also print the cases that ended so")
    args = parser.parse_args()
    import logging

    logging.disable(logging.WARNING)  # the loaded cases' warning lines
    counts: Counter[str] = Counter()
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="omtp_world_fuzz_") as folder:
        for case in range(args.cases):
            outcome, detail = run_case(case, args.seed, Path(folder))
            counts[outcome] += 1
            if outcome == "FINDING" or outcome == args.show:
                print(f"{outcome}: {detail}", flush=True)
    elapsed = time.perf_counter() - start
    print(f"{args.cases} cases (seed {args.seed}) in {elapsed:.0f} s: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))


if __name__ == "__main__":
    main()
