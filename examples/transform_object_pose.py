"""Lecture 6: where is the part logical camera 1 sees, in the world? (tf2's transform)

    python examples/transform_object_pose.py
"""

import argparse

from omtp_drake import Cell


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.parse_args(argv)
    with Cell("lecture6_assignment1") as cell:         # a part resting on the belt under camera 1
        cell.wait(0.5)
        image = cell.camera("logical_camera_1").image()
        seen = image.pose_of("object_1")               # in logical_camera_1_frame, at the image's time
        in_world = cell.tf.transform_pose(seen, "world")
        p = in_world.pose.translation()
        print(f"camera 1 saw object_1 at t = {image.time:.1f} s; in world: "
              f"({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f})")
        return {"p_W": p, "truth": cell.part_pose("object_1").translation()}


if __name__ == "__main__":
    main()
