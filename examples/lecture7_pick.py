"""Lecture 7: the break beam stops each part under camera 1; robot 1 picks it off the belt
into bin 2, then starts the belt again.

    python examples/lecture7_pick.py [--parts 2] [--record replay.html]
"""

import argparse

from omtp_drake import Cell, tool_down


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", type=int, default=2, help="parts to pick (0.2 m cubes: 2 fit)")
    parser.add_argument("--record", metavar="HTML", help="write a Meshcat replay")
    args = parser.parse_args(argv)
    with Cell("lecture7_conveyor_pick", record=args.record) as cell:  # belt on, a part every 3 s
        arm, vacuum = cell.arm("robot1"), cell.gripper("robot1")
        camera = cell.camera("logical_camera_1")
        bin_2 = cell.tf.lookup_transform("world", "bin_2_base_link").transform.translation()
        arm.go("Home")
        for _ in range(args.parts):
            cell.wait_until(cell.break_beam, timeout=20, what="a part at the break beam")
            cell.wait(0.5)                                   # the belt has stopped it
            part, seen = next(iter(camera.parts().items()))
            p = cell.tf.transform_pose(seen, "world").pose.translation()
            arm.move_to(tool_down(p + [0, 0, 0.2]))          # above the part, tool down
            vacuum.on()
            arm.move_linear(tool_down(p + [0, 0, 0.08]), speed=0.05, until=lambda: vacuum.attached)
            arm.move_linear(tool_down(p + [0, 0, 0.35]))     # straight up off the belt
            arm.move_to(tool_down(bin_2 + [0, 0, 0.75]))     # over bin 2 (rim at 0.475 m)
            vacuum.off()
            cell.wait(0.5)
            cell.set_conveyor_power(100)                     # the next part may come
            print(f"t = {cell.time:5.1f} s: {part} is {cell.ledger().parts[part]}")
        ledger = cell.ledger()
        print(ledger.summary_line())
        return {"ledger": ledger}


if __name__ == "__main__":
    main()
