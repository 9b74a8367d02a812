"""A robot with 20 converted meshes: load time with an empty mesh cache and with a full one.

The robot is the test fixture's fr7 arm with its hand (``tests/fixtures/franka_ws``: a
franka_description-style package, 10 ``.dae`` visuals and 10 ``.stl`` collisions, 22
mesh references). One load is what ``omtp-drake view`` does before drawing: xacro
expanded, meshes made Drake-ready, the model parsed into a plant, the plant finalized.
Imports are warmed first; each round uses a new empty cache folder for the first load,
then loads again from that cache.

    python bench/bench_meshes.py [--rounds 5]
"""

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "tests" / "fixtures" / "franka_ws" / "src"
ROBOT = SRC / "fr7_description" / "urdf" / "fr7.urdf.xacro"


def _load() -> tuple[float, float]:
    """(seconds to expand the xacro, seconds for the whole load)."""
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    from omtp_drake.cell.described_models import add_described_models
    from omtp_drake.scenario.models import file_workspace, model_from_file

    start = time.perf_counter()
    model = model_from_file(ROBOT, file_workspace(ROBOT, [SRC]), static=True)
    expanded = time.perf_counter()
    plant = MultibodyPlant(0.0)
    add_described_models(Parser(plant), [model], gazebo_look=False)
    plant.Finalize()
    return expanded - start, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    import trimesh  # noqa: F401  (imports warmed: they are not the conversion's cost)

    from omtp_drake import assets

    conversions = []
    convert = assets.convert_mesh

    def counting(src, dst):
        conversions.append(src)
        convert(src, dst)

    assets.convert_mesh = counting
    with tempfile.TemporaryDirectory() as warm:
        os.environ["OMTP_DRAKE_CACHE"] = warm
        _load()
    first, cached, xacro, converted = [], [], [], []
    for _ in range(args.rounds):
        with tempfile.TemporaryDirectory() as cache:
            os.environ["OMTP_DRAKE_CACHE"] = cache
            conversions.clear()
            first.append(_load()[1])
            converted.append(len(conversions))
            conversions.clear()
            xacro_s, total = _load()
            cached.append(total)
            xacro.append(xacro_s)
            assert not conversions, "the second load converted again"
    med = statistics.median
    print(f"robot: {ROBOT.relative_to(ROOT)} ({converted[0]} meshes converted per first load)")
    print(f"first load (empty cache): {med(first) * 1e3:7.0f} ms median of {args.rounds}")
    print(f"cached load:              {med(cached) * 1e3:7.0f} ms median of {args.rounds}")
    print(f"  of which xacro:         {med(xacro) * 1e3:7.0f} ms (expansion, the same in both)")
    print(f"conversion per mesh:      {(med(first) - med(cached)) / converted[0] * 1e3:7.1f} ms")
    print(f"load average: {' '.join(f'{v:.1f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
