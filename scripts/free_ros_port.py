#!/usr/bin/env python3
"""Prints a free TCP port on loopback for a ROS master, below Linux's ephemeral range
(32768-60999) where rostest's own masters and every node's XML-RPC server take theirs, so
tests running in parallel cannot grab it between this check and its use."""
import random
import socket
import sys

for port in random.sample(range(20000, 32000), 500):
    with socket.socket() as s:
        try:
            s.bind(("127.0.0.1", port))
        except OSError:
            continue
    print(port)
    sys.exit(0)
sys.exit("no free port in 20000-32000")
