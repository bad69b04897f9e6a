#!/usr/bin/env bash
# Every command-line tool in devel/bin shares one argument and error handling
# (flagella_sim/runtime/tool_main.h): --help prints the usage and exits 0, an unknown argument
# exits 2 with a message naming it (CLI11's own codes were 105-113), and a config that does not
# exist exits 2 naming the file, never an abort ("terminate called ...", exit 134).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/scratch_dir.sh"
bin="$root/devel/bin"
count=0
for tool in "$bin"/flagella_*; do
  name=$(basename "$tool")
  status=0
  out=$("$tool" --help 2>&1) || status=$?
  [[ $status -eq 0 ]] || fail "$name --help exited $status"
  [[ "$out" == *"Usage"* || "$out" == *"usage"* ]] || fail "$name --help printed no usage"
  status=0
  out=$("$tool" --xyzzy 2>&1) || status=$?
  [[ $status -eq 2 ]] || fail "$name --xyzzy exited $status (expected 2): $out"
  [[ "$out" == *"--help for the usage"* ]] || fail "$name --xyzzy: message without the hint: $out"
  [[ "$out" != *"terminate called"* ]] || fail "$name --xyzzy aborted: $out"
  count=$((count + 1))
done
[[ $count -ge 15 ]] || fail "only $count tools found in $bin"
# A missing config: exit 2 naming the file (the tools that take a config as first argument).
for cmd in "flagella_run run" "flagella_buckling" "flagella_follow_path" "flagella_lcm_harness"; do
  status=0
  out=$("$bin"/$cmd "$work/none.yaml" 2>&1) || status=$?
  [[ $status -eq 2 ]] || fail "$cmd none.yaml exited $status (expected 2): $out"
  [[ "$out" == *"none.yaml"* ]] || fail "$cmd none.yaml: message does not name the file: $out"
done
echo "tool_arguments: $count tools: --help 0, unknown argument 2, missing config 2"
