#!/usr/bin/env python3
"""The launch files as roslaunch reads them (rostest launch_files.test):

- `roslaunch --ros-args` lists as required only what has no sensible default
  (bag.launch's bag), and documents every argument;
- with every option switched on, each node's executable exists and each
  nodelet loaded is a declared plugin (image_proc/rectify, image_view, rviz,
  risas's own), as roslaunch-check would find at start.
"""
import os
import subprocess
import unittest
import xml.etree.ElementTree as ET

import rosunit
import roslaunch.config
import roslaunch.xmlloader
import roslib.packages
import rospkg

PACKAGE = rospkg.RosPack().get_path("risas")
LAUNCH = os.path.join(PACKAGE, "launch")
# Every option on, so that conditional nodes are checked too.
ALL_ON = {
    "demo.launch": ["view:=true", "rviz:=true", "save:=/tmp/overlay_%04i.png"],
    "risas.launch": ["odometry:=true"],
    "bag.launch": ["bag:=/tmp/any.bag", "odometry:=true", "loop:=true"],
    "openni2.launch": ["view:=true", "odometry:=true", "camera_info_url:=file:///tmp/rgb.yaml"],
    "odometry.launch": ["base_frame_id:=base_link"],
}
REQUIRED = {"bag.launch": ["bag"]}


def declared_nodelets():
    names = set()
    out = subprocess.run(["rospack", "plugins", "--attrib=plugin", "nodelet"], capture_output=True, text=True).stdout
    for line in out.splitlines():
        package, path = line.split(" ", 1)
        path = path.strip()
        root = ET.parse(path).getroot()
        for library in ([root] if root.tag == "library" else root.iter("library")):
            for cls in library.iter("class"):
                names.add(cls.get("name") or cls.get("type"))
    return names


class LaunchFiles(unittest.TestCase):
    def test_every_launch_file_is_checked(self):
        self.assertEqual(sorted(f for f in os.listdir(LAUNCH) if f.endswith(".launch")), sorted(ALL_ON))

    def test_only_real_requirements_are_listed_as_required_and_every_argument_is_documented(self):
        for name in ALL_ON:
            out = subprocess.run(["roslaunch", "--ros-args", os.path.join(LAUNCH, name)],
                                 capture_output=True, text=True, check=True).stdout
            required, section = [], None
            for line in out.splitlines():
                if line.endswith("Arguments:"):
                    section = line
                elif section == "Required Arguments:":
                    required.append(line.strip().split(":")[0])
                self.assertNotIn("undocumented", line, name)
            self.assertEqual(required, REQUIRED.get(name, []), name + "\n" + out)

    def test_with_every_option_on_each_node_and_nodelet_exists(self):
        nodelets = declared_nodelets()
        for name, args in ALL_ON.items():
            loader = roslaunch.xmlloader.XmlLoader()
            config = roslaunch.config.ROSLaunchConfig()
            loader.load(os.path.join(LAUNCH, name), config, argv=["roslaunch"] + args, verbose=False)
            self.assertTrue(config.nodes, name)
            for node in config.nodes + config.tests:
                self.assertTrue(roslib.packages.find_node(node.package, node.type),
                                "%s: no executable %s/%s" % (name, node.package, node.type))
                words = node.args.split()
                if node.package == "nodelet" and words and words[0] == "load":
                    self.assertIn(words[1], nodelets, "%s: nodelet %s is not declared" % (name, words[1]))


if __name__ == "__main__":
    rosunit.unitrun("risas", "launch_files", LaunchFiles)
