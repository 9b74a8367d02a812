"""Lecture 6, assignment 4: robot 2 picks each part from the floor into bin 1, again and again.

    python examples/lecture6_assignment4.py [--parts 2] [--record replay.html]
"""

import argparse

from omtp_drake import Cell, tool_down


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--parts", type=int, default=2, help="parts to pick (0.2 m cubes: 2 fit)")
    parser.add_argument("--record", metavar="HTML", help="write a Meshcat replay")
    args = parser.parse_args(argv)
    with Cell("lecture6_assignment4", auto_spawn=False, record=args.record) as cell:
        arm, vacuum = cell.arm("robot2"), cell.gripper("robot2")
        camera = cell.camera("logical_camera_2")
        for _ in range(args.parts):
            arm.go("Home")
            part = cell.spawn_part()                  # dropped next to robot 2
            cell.wait(1.5)                            # it falls and comes to rest
            seen = cell.tf.transform_pose(camera.image().pose_of(part), "world")
            p = seen.pose.translation()               # the part's centre (a 0.2 m cube)
            arm.move_to(tool_down(p + [0, 0, 0.2]))   # cup face 0.1 m above the top face
            vacuum.on()
            arm.move_linear(tool_down(p + [0, 0, 0.08]), speed=0.05, until=lambda: vacuum.attached)
            arm.go("Home")
            arm.go("Place")                           # R2Place: above bin 1
            vacuum.off()
            cell.wait(0.5)                            # it drops into the bin
            print(f"t = {cell.time:5.1f} s: {part} is {cell.ledger().parts[part]}")
        ledger = cell.ledger()
        print(ledger.summary_line())
        return {"ledger": ledger}


if __name__ == "__main__":
    main()
