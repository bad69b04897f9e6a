#!/usr/bin/env bash
# Configures and builds the catkin workspace (Release), including the test executables.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
cd "$FLAGELLA_ROOT"
# A failed configure is cached by catkin: start over if the last one did not finish.
if [ -d build ] && [ ! -f build/Makefile ]; then rm -rf build devel; fi
catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release -DCATKIN_ENABLE_TESTING=ON \
  -j"$(nproc)" > build.log 2>&1 || { tail -50 build.log; echo "build failed (full log: build.log)"; exit 1; }
# catkin caches the devel environment (PYTHONPATH, LD_LIBRARY_PATH) at configure time and only
# lists folders that exist then: on a fresh clone the generated python messages are missing from
# it, and rostest's python nodes could not import them. Configure once more after the first build.
if grep -q "^export PYTHONPATH=''" build/catkin_generated/setup_cached.sh; then
  cmake build >> build.log 2>&1 || { tail -50 build.log; echo "reconfigure failed"; exit 1; }
fi
make -C build -j"$(nproc)" tests >> build.log 2>&1 || { tail -50 build.log; echo "building tests failed (full log: build.log)"; exit 1; }
echo "build: ok (log: build.log)"
