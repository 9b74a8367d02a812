"""Lecture 6, assignment 3: a part next to robot 2; its pose in the suction-cup frame.

    python examples/lecture6_assignment3.py
"""

import argparse

from pydrake.math import RollPitchYaw

from omtp_drake import Cell


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.parse_args(argv)
    with Cell("lecture6_assignment3") as cell:         # object_1 drops next to robot 2
        cell.wait(1.5)                                 # it has landed under camera 2
        seen = cell.camera("logical_camera_2").image().pose_of("object_1")
        in_cup = cell.tf.transform_pose(seen, "vacuum_gripper2_suction_cup")
        p, rpy = in_cup.pose.translation(), RollPitchYaw(in_cup.pose.rotation()).vector()
        print(f"object_1 in vacuum_gripper2_suction_cup at t = {in_cup.time:.1f} s:")
        print(f"  translation ({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) m, rpy ({rpy[0]:.3f}, "
              f"{rpy[1]:.3f}, {rpy[2]:.3f}) rad")
        truth = cell.arm("robot2").tool_pose("suction_cup").InvertAndCompose(cell.part_pose("object_1"))
        return {"X_SP": in_cup.pose, "truth": truth}


if __name__ == "__main__":
    main()
