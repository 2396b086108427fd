#!/usr/bin/env bash
# The README's first command: sets up (Debian 12 packages), builds pcl_icf_tool (release
# preset), finds the bundled Box5 in the bundled table-top scene and writes out/demo/:
#   result.json  the clusters and the best pose (doc/USER_GUIDE.md)
#   box5_posed.ply  the model moved to its pose, in the scene's frame
#   result.png   the scene seen from the camera with the posed model drawn over it
# No display is needed: the tool renders under xvfb-run when DISPLAY is unset.
# The tool's exit code passes through: 0 found, 1 nothing accepted, 2 bad input.
#   JOBS=N scripts/demo.sh   (build parallelism, default: all cores)
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target pcl_icf_tool -j "${JOBS:-$(nproc)}"

out=out/demo
mkdir -p "$out"
status=0
build/release/tools/pcl_icf_tool data/demo/tabletop_box5.pcd data/demo/box5.ply \
  --json "$out/result.json" --output "$out/box5_posed.ply" --render "$out/result.png" \
  --force || status=$?

echo
echo "ground truth (data/demo/tabletop_box5_truth.txt, model -> camera, metres):"
sed 's/^/       /' data/demo/tabletop_box5_truth.txt
if [ -f "$out/result.png" ]; then
  echo
  echo "picture: $(pwd)/$out/result.png"
fi
exit "$status"
