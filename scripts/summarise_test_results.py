#!/usr/bin/python3
"""Counts the test cases in JUnit XML results (catkin's folders of them, and
ctest's --output-junit files) and prints one closing line, 'N passed,
N failed', exiting 1 when any failed, errored or no test ran.
A rostest leaves two files: rosunit-*.xml with the test node's own cases and a
rostest-*.xml wrapper, read for failures only (a node that never started
shows there alone), so that passes are not counted twice."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

def result_files(args):
    for arg in args:
        path = Path(arg)
        if path.is_dir():
            yield from sorted(path.rglob("*.xml"))
        elif path.exists():
            yield path
        else:
            print(f"{path}: no test results (the stage did not run its tests)")
            yield None


passed = failed = skipped = 0
for xml in result_files(sys.argv[1:]):
    if xml is None:
        failed += 1
        continue
    try:
        root = ET.parse(xml).getroot()
    except ET.ParseError as e:
        print(f"{xml}: unreadable result file ({e})")
        failed += 1
        continue
    wrapper = xml.name.startswith("rostest-")
    for case in root.iter("testcase"):
        if case.find("failure") is not None or case.find("error") is not None:
            failed += 1
            print(f"FAILED: {case.get('classname')}.{case.get('name')}")
        elif wrapper:
            continue
        elif case.find("skipped") is not None or case.get("status") in ("notrun", "disabled"):
            skipped += 1
        else:
            passed += 1

print(f"{passed} passed, {failed} failed, {skipped} skipped")
sys.exit(1 if failed or passed == 0 else 0)
