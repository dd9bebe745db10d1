#!/usr/bin/env python3
"""Count the test cases in the JUnit XML files under a catkin test_results folder and print
`N passed, N failed, N skipped` as the last line, each failed case before it with its message
(`  why: ...`, one line). A skipped case is not a pass. Exit 1 when
any case failed, errored, or when no case ran at all."""
import os
import sys
import xml.etree.ElementTree as ET


def why(problem, limit=1500):
    """The failure's message on one line (CI shows only the end of a long log)."""
    text = " ".join(((problem.get("message") or "") + " " + (problem.text or "")).split())
    return text[:limit] + (" [...]" if len(text) > limit else "") if text else "(no message)"


def main(folder):
    passed = failed = skipped = 0
    for dirpath, _, files in os.walk(folder):
        for name in sorted(files):
            if not name.endswith(".xml"):
                continue
            path = os.path.join(dirpath, name)
            try:
                tree = ET.parse(path)
            except ET.ParseError as err:
                print("unreadable result file %s: %s" % (path, err))
                failed += 1
                continue
            for case in tree.iter("testcase"):
                problem = case.find("failure")
                if problem is None:
                    problem = case.find("error")
                if problem is not None:
                    failed += 1
                    print("FAILED: %s.%s (%s)" % (case.get("classname"), case.get("name"), name))
                    print("  why: %s" % why(problem))
                elif case.find("skipped") is not None or case.get("status") == "notrun":
                    skipped += 1
                    print("SKIPPED: %s.%s (%s)" % (case.get("classname"), case.get("name"), name))
                else:
                    passed += 1
    print("%d passed, %d failed, %d skipped" % (passed, failed, skipped))
    return 1 if failed or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else "build/test_results"))
