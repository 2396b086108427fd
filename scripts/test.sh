#!/usr/bin/env bash
# Sets up, builds and runs every test: the release build and, unless SKIP_SANITIZERS=1, an
# ASan+UBSan build of the tests; with RUN_TSAN=1 (.ci/run sets it) also a ThreadSanitizer build
# of the multi-threaded tests (clang, libomp + Archer: doc/HOSTILE_INPUTS.md). Installs the
# Python module for this user after the release tests. Used by the README and by .ci/run.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each step's wall time, so that a slow run says where its time went.
timed() {
  local t0
  t0=$(date +%s)
  "$@"
  echo "test.sh: $* took $(($(date +%s) - t0)) s"
}
timed scripts/setup.sh
JOBS=${JOBS:-$(nproc)}

# PCL_ICF_PYTHON: the Python module and its pytest suite (ctest runs it), release build only.
# PCL_ICF_BENCH_PEERS=ON: Open3D's and OpenCV's methods in pcl_icf_bench, required.
cmake --preset release -DPCL_ICF_PYTHON=ON -DPCL_ICF_BENCH_PEERS=ON >/dev/null
timed cmake --build --preset release -j "$JOBS"
timed ctest --preset release -j "$JOBS"
# The module where this user's python3 finds it (`python3 -c "import pcl_icf"` from anywhere),
# once its tests passed: Python's per-user site folder, no system folder touched.
site=$(/usr/bin/python3 -m site --user-site)
install -D -m 644 build/release/python/pcl_icf.cpython-*.so -t "$site"
echo "test.sh: Python module pcl_icf installed in $site"

if [ "${SKIP_SANITIZERS:-0}" != 1 ]; then
  cmake --preset asan >/dev/null
  timed cmake --build --preset asan -j "$JOBS"
  timed ctest --preset asan -j "$JOBS"
fi

if [ "${RUN_TSAN:-0}" = 1 ]; then
  cmake --preset tsan >/dev/null
  timed cmake --build --preset tsan -j "$JOBS"
  timed ctest --preset tsan -j "$JOBS"
fi
