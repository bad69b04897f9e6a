#!/usr/bin/env python3
"""Checks a bag recorded by launch/sim.launch: it is closed and readable, and it contains every
message the simulator published. Two independent counts per topic:
  - the simulator's own count, reported in its last /diagnostics message ("published <topic>"),
    which was published after everything else (so /diagnostics itself has one more);
  - the schedule: one message at t = 0 plus one per period over the duration
    (diagnostics: plus the final report).
"""
import argparse
import math
import sys

import rosbag


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("bag")
    parser.add_argument("--duration", type=float, required=True)
    parser.add_argument("--rate", action="append", default=[], help="topic=Hz")
    args = parser.parse_args()

    counts = {}
    last_diagnostics = None
    with rosbag.Bag(args.bag) as bag:
        for topic, msg, _ in bag.read_messages():
            counts[topic] = counts.get(topic, 0) + 1
            if topic == "/diagnostics":
                for status in msg.status:
                    if "flagella_sim" in status.name:
                        last_diagnostics = status
    if last_diagnostics is None:
        print("FAIL: no flagella_sim diagnostics in the bag")
        return 1
    reported = {kv.key[len("published "):]: int(kv.value)
                for kv in last_diagnostics.values if kv.key.startswith("published ")}

    failures = 0
    print("%-22s %8s %8s %8s" % ("topic", "in bag", "sim said", "schedule"))
    for item in args.rate:
        topic, rate = item.split("=")
        rate = float(rate)
        in_bag = counts.get(topic, 0)
        said = reported.get(topic, 0) + (1 if topic == "/diagnostics" else 0)
        schedule = int(math.floor(args.duration * rate + 1e-9)) + 1
        if topic == "/diagnostics":
            schedule += 1  # the final report
        ok = in_bag == said == schedule
        failures += not ok
        print("%-22s %8d %8d %8d %s" % (topic, in_bag, said, schedule, "ok" if ok else "MISMATCH"))
    total = sum(counts.get(item.split("=")[0], 0) for item in args.rate)
    print("total messages checked: %d" % total)
    if failures:
        print("FAIL: %d topic(s) do not match" % failures)
        return 1
    print("PASS: the bag holds every published message")
    return 0


if __name__ == "__main__":
    sys.exit(main())
