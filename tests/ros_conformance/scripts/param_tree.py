#!/usr/bin/env python
# Parameters as a tree: a dictionary under a relative name, read back leaf by leaf and
# as a namespace; private parameters under the node.
import json
import sys

import rospy

if __name__ == "__main__":
    rospy.init_node("param_user")
    rospy.set_param("place/bin_1", {"x": -8.0, "y": -2.2, "drop": {"z": 1.0}})
    rospy.set_param("~speed", 0.5)
    result = {
        "leaf": rospy.get_param("/place/bin_1/drop/z"),
        "namespace": rospy.get_param("place"),
        "private": rospy.get_param("/param_user/speed"),
        "all_keys": sorted(rospy.get_param("/").keys()),
        "has": [rospy.has_param("place/bin_1/x"), rospy.has_param("place/bin_2")],
        "default": rospy.get_param("place/bin_2", "none"),
    }
    rospy.delete_param("place")
    result["after_delete"] = rospy.has_param("/place/bin_1/x")
    try:
        rospy.get_param("place")
    except KeyError as e:
        result["error"] = str(e)
    with open(sys.argv[1], "w") as f:
        json.dump(result, f)
