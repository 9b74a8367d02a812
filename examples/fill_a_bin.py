"""The challenge: robot 2 fills bin 1 with 0.1 m cubes, squared in a 3 x 3 grid per layer.

    python examples/fill_a_bin.py [--parts 10] [--record replay.html]
"""

import argparse

import numpy as np

from omtp_drake import Cell, tool_down, yaw_of


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", type=int, default=10)
    parser.add_argument("--record", metavar="HTML", help="write a Meshcat replay")
    args = parser.parse_args(argv)
    with Cell("fill_bin", record=args.record) as cell:   # a part is dropped whenever none is loose
        arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
        camera = cell.camera("logical_camera_2")
        X_WB = cell.tf.lookup_transform("world", "bin_1_base_link").transform
        for k in range(args.parts):
            arm.go("Home")
            cell.wait_until(lambda: camera.parts(), timeout=10, what="a part under camera 2")
            cell.wait(1.0)                                       # let it come to rest
            part, seen = next(iter(camera.parts().items()))
            pose = cell.tf.transform_pose(seen, "world").pose
            p, yaw = pose.translation(), yaw_of(pose)            # a 0.1 m cube, turned by yaw
            arm.move_to(tool_down(p + [0, 0, 0.15], yaw))
            vacuum.on()
            arm.move_linear(tool_down(p + [0, 0, 0.04], yaw), speed=0.05, until=lambda: vacuum.attached)
            arm.move_linear(tool_down(p + [0, 0, 0.3], yaw))
            layer, (row, col) = divmod(k, 9)[0], divmod(k % 9, 3)
            slot = X_WB @ np.array([0.127 * (row - 1), 0.127 * (col - 1), 0.475 + 0.02])
            arm.move_to(tool_down(slot + [0, 0, 0.1]))           # squared with the bin (yaw 0)
            arm.move_linear(tool_down(slot))                     # just above the rim
            vacuum.off()
            cell.wait(0.4)                                       # it drops into its slot
            print(f"t = {cell.time:5.1f} s: {part} (layer {layer}) is {cell.ledger().parts[part]}")
        ledger = cell.ledger()
        print(ledger.summary_line())
        return {"ledger": ledger}


if __name__ == "__main__":
    main()
