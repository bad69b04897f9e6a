#!/usr/bin/env python3
"""Runs every ```bash block of README.md as a new user would: each block in a fresh, clean shell
(env -i: only HOME, PATH, LANG; no ROS variables, nothing sourced) from the repository root,
with bash -e, so every command of the block must succeed.

Long runs are shortened, and the few lines that cannot run here are left out, by directives in an
HTML comment right above the block in README.md (invisible on the rendered page, in plain sight
in its source):

  <!-- readme-test: replace "TEXT" "SHORTER" -->   every TEXT in the block becomes SHORTER; TEXT
                                                  must occur (a stale directive is an error)
  <!-- readme-test: skip-line "START" REASON -->   leaves out the command line starting with START
                                                  (with its continuation lines); it must exist
  <!-- readme-test: session LAUNCH [ARGS] -->      runs `scripts/roslaunch_session.py LAUNCH ARGS`
                                                  in the background first (a block of commands for
                                                  a running session), stopped afterwards
  <!-- readme-test: timeout SECONDS -->            the block's time limit (default 600 s)

The shell gets FLAGELLA_ROS_PORT (a free port, so sessions cannot collide with another master)
and, for mpirun as root in a container, OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM)=1 and oversubscription.

Usage: readme_commands.py [--readme README.md] [--only N[,N...]] [--list]
Exit 0 when every block ran, 1 otherwise; prints one line per block and a summary.
"""
import argparse
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DIRECTIVE = re.compile(r"<!--\s*readme-test:\s*(.*?)\s*-->")
DEFAULT_TIMEOUT = 600.0


class Block:
    def __init__(self, number, line, text, directives):
        self.number, self.line, self.text, self.directives = number, line, text, directives


def read_blocks(path):
    """The bash blocks of a Markdown file with the directives right above each."""
    blocks, pending, lines = [], [], open(path).read().split("\n")
    i = 0
    while i < len(lines):
        line = lines[i]
        m = DIRECTIVE.search(line)
        if m:
            pending.append(m.group(1))
        elif line.strip() == "```bash":
            start = i + 1
            j = start
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            blocks.append(Block(len(blocks), start, "\n".join(lines[start:j]) + "\n", pending))
            pending = []
            i = j
        elif line.strip():
            pending = []
        i += 1
    return blocks


def logical_lines(text):
    """Physical lines grouped into commands (a line ending in a backslash continues)."""
    groups, current = [], []
    for line in text.split("\n"):
        current.append(line)
        if not line.rstrip().endswith("\\"):
            groups.append(current)
            current = []
    if current:
        groups.append(current)
    return groups


def prepare(block):
    """The block's script after its directives; (script, session args, timeout, notes)."""
    text, session, timeout, notes = block.text, None, DEFAULT_TIMEOUT, []
    for d in block.directives:
        words = shlex.split(d)
        kind, args = words[0], words[1:]
        if kind == "replace" and len(args) == 2:
            if args[0] not in text:
                raise ValueError("replace: %r is not in the block" % args[0])
            text = text.replace(args[0], args[1])
            notes.append("%s -> %s" % (args[0], args[1]))
        elif kind == "skip-line" and len(args) >= 2:
            groups = logical_lines(text)
            kept = [g for g in groups if not g[0].lstrip().startswith(args[0])]
            if len(kept) == len(groups):
                raise ValueError("skip-line: no command starts with %r" % args[0])
            text = "\n".join(line for g in kept for line in g)
            notes.append("left out %r (%s)" % (args[0], " ".join(args[1:])))
        elif kind == "session" and args:
            session = args
        elif kind == "timeout" and len(args) == 1:
            timeout = float(args[0])
        else:
            raise ValueError("unknown directive %r" % d)
    return text, session, timeout, notes


def clean_environment(home):
    env = {"HOME": home, "LANG": "C.UTF-8",
           "PATH": "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin",
           "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1"}
    port = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts/free_ros_port.py")],
                          capture_output=True, text=True, check=True).stdout.strip()
    env["FLAGELLA_ROS_PORT"] = port
    env["ROS_HOME"] = os.path.join(home, "ros_home")
    return env


def start_session(args, env, log):
    """A session in the background for a block of commands to a running session."""
    command = "source scripts/ros_env.sh 2>/dev/null && exec /usr/bin/python3 " \
              "scripts/roslaunch_session.py " + " ".join(shlex.quote(a) for a in args)
    proc = subprocess.Popen(["bash", "-c", command], cwd=ROOT, env=env, stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True)
    wait = "source scripts/ros_env.sh 2>/dev/null && rosservice list 2>/dev/null | grep -q /sim/reset"
    deadline = time.time() + 120
    while time.time() < deadline:
        if subprocess.run(["bash", "-c", wait], cwd=ROOT, env=env).returncode == 0:
            return proc
        if proc.poll() is not None:
            break
        time.sleep(1)
    stop(proc)
    raise RuntimeError("the session %s did not come up" % " ".join(args))


def stop(proc):
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGINT)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def run_block(block, keep_logs):
    script, session, timeout, notes = prepare(block)
    home = tempfile.mkdtemp(prefix="readme_home.")
    env = clean_environment(home)
    log_path = os.path.join(home, "block.log")
    started = time.time()
    with open(log_path, "w") as log:
        proc = None
        try:
            if session:
                proc = start_session(session, env, log)
            result = subprocess.run(["bash", "-e", "-o", "pipefail", "-c", script], cwd=ROOT,
                                    env=env, stdout=log, stderr=subprocess.STDOUT, timeout=timeout,
                                    start_new_session=True)
            status = result.returncode
        except subprocess.TimeoutExpired:
            status = "timeout after %.0f s" % timeout
        except RuntimeError as e:
            status = str(e)
        finally:
            if proc:
                stop(proc)
    if status == 0 and not keep_logs:
        subprocess.run(["rm", "-rf", home])
    return status, time.time() - started, notes, log_path, script


def main():
    parser = argparse.ArgumentParser(description="runs the README's command blocks")
    parser.add_argument("--readme", default=os.path.join(ROOT, "README.md"))
    parser.add_argument("--only", help="block numbers, comma separated (see --list)")
    parser.add_argument("--list", action="store_true", help="list the blocks and their directives")
    args = parser.parse_args()
    blocks = read_blocks(args.readme)
    if args.only:
        wanted = {int(n) for n in args.only.split(",")}
        blocks = [b for b in blocks if b.number in wanted]
    if args.list:
        for b in blocks:
            print("block %d (README line %d): %s" % (b.number, b.line, "; ".join(b.directives) or "verbatim"))
        return 0
    failures = 0
    total_started = time.time()
    for b in blocks:
        try:
            status, wall, notes, log_path, script = run_block(b, keep_logs=False)
        except ValueError as e:
            status, wall, notes, log_path, script = "bad directive: %s" % e, 0.0, [], None, ""
        ok = status == 0
        failures += not ok
        print("block %2d (README line %4d): %-4s %6.1f s%s" % (
            b.number, b.line, "ok" if ok else "FAIL", wall,
            ("; " + "; ".join(notes)) if notes else ""), flush=True)
        if not ok:
            print("  status: %s\n  script:\n%s" % (status, "\n".join("    " + l for l in script.split("\n"))))
            if log_path and os.path.exists(log_path):
                tail = open(log_path, errors="replace").read().split("\n")[-40:]
                print("  last lines of its output:\n" + "\n".join("    " + l for l in tail))
    print("README command blocks: %d of %d ran, %.0f s" % (len(blocks) - failures, len(blocks),
                                                           time.time() - total_started))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
