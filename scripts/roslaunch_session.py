#!/usr/bin/env python3
"""Runs a launch file as roslaunch does, and ends it the way a batch session should.

Usage: roslaunch_session.py LAUNCH_FILE [NAME:=VALUE ...]

roslaunch itself exits 0 whatever happened, ends every finished session with a red "REQUIRED
process has died!" banner and keeps waiting when a node cannot be started. This runs the same
launch file on the master at ROS_MASTER_URI (started when none is running) and:
  - a node that cannot be started (its package not built, or devel/setup.bash not sourced in
    this shell) is an error naming it: everything is stopped, exit 1;
  - when a node marked required="true" ends, the others are stopped and the exit code is that
    node's (0 when it finished, e.g. after `duration`; non-zero on a configuration error);
  - Ctrl-C stops everything, exit 130.
"""
import os
import sys
import threading

import rosgraph.names
import roslaunch
import roslaunch.parent
import roslaunch.pmon
import roslaunch.rlutil
from roslaunch.core import RLException


class SessionEnd(roslaunch.pmon.ProcessListener):
    """Notes the first required node to end and the exit codes of every node that failed."""

    def __init__(self, required):
        self.required = set(required)
        self.ended = threading.Event()
        self.exit_code = 0
        self.ended_by = None
        self.failures = []

    def process_died(self, process_name, exit_code):
        node = process_name.rsplit("-", 1)[0]  # roslaunch names a node's process "<name>-<k>"
        if exit_code:
            self.failures.append((node, exit_code))
        if node in self.required and not self.ended.is_set():
            self.ended_by = node
            self.exit_code = exit_code if exit_code is not None else 1
            self.ended.set()


def node_name(node):
    return rosgraph.names.ns_join(node.namespace, node.name).lstrip("/")


def main(argv):
    if len(argv) < 1 or argv[0] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if argv else 2
    launch_file, launch_args = os.path.abspath(argv[0]), argv[1:]
    if not os.path.isfile(launch_file):
        print(f"roslaunch_session: no launch file '{argv[0]}'", file=sys.stderr)
        return 2
    bad = [a for a in launch_args if ":=" not in a]
    if bad:
        print(f"roslaunch_session: '{bad[0]}' is not NAME:=VALUE", file=sys.stderr)
        return 2

    run_id = roslaunch.rlutil.get_or_generate_uuid(None, False)
    roslaunch.configure_logging(run_id)
    parent = roslaunch.parent.ROSLaunchParent(run_id, [(launch_file, launch_args)], is_core=False)
    try:
        parent._load_config()  # noqa: the documented start() would not let us see the nodes first
    except RLException as e:
        print(f"roslaunch_session: {e}", file=sys.stderr)
        return 2
    # The required flags move from roslaunch's process monitor (the banner, exit 0) to here.
    required = [node_name(n) for n in parent.config.nodes if n.required]
    for n in parent.config.nodes:
        n.required = False
    session = SessionEnd(required)
    try:
        parent._start_infrastructure()
        parent.pm.add_process_listener(session)
        parent._init_runner()
        _, failed = parent.runner.launch()
        parent.pm.registrations_complete()
        if failed:
            print("roslaunch_session: could not start " + ", ".join(failed) + ": is the workspace "
                  "built and its devel/setup.bash sourced in this shell (source "
                  "scripts/ros_env.sh)?", file=sys.stderr)
            return 1
        while not session.ended.wait(0.2):
            if parent.pm.is_shutdown or parent.pm.done:
                break
    except KeyboardInterrupt:
        return 130
    except RLException as e:
        print(f"roslaunch_session: {e}", file=sys.stderr)
        return 1
    finally:
        parent.shutdown()
    if session.ended_by is not None:
        print(f"roslaunch_session: {session.ended_by} ended the session, exit code "
              f"{session.exit_code}")
        return session.exit_code
    if session.failures:
        node, code = session.failures[0]
        print(f"roslaunch_session: {node} failed, exit code {code}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
