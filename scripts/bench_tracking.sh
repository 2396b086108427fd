#!/usr/bin/env bash
# The synthetic tracking bars (doc/BENCHMARKS.md "Tracking"): writes N sequences with
# pcl_icf_make_dataset --kind sequence, tracks each with pcl_icf_tool --track (its two tracked
# models), and scores the poses against the ground truth with pcl_icf_track_score.
#   scripts/bench_tracking.sh [SEQUENCES (3)] [FRAMES (40)] [SEED (1515)]
# Needs the release build of pcl_icf_make_dataset, pcl_icf_tool and pcl_icf_track_score
# (BIN=folder to use another). Writes out/track_bench/ (OUT=folder); exit status: the
# scorer's (0 bars met, 1 not met, 2 bad input).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$(realpath "${BIN:-build/release/tools}")
out=${OUT:-out/track_bench}
sequences=${1:-3} frames=${2:-40} seed=${3:-1515}

rm -rf "$out/sequence"
"$bin/pcl_icf_make_dataset" --kind sequence --cases "$sequences" --frames "$frames" \
  --seed "$seed" --out "$out"
for seq in "$out"/sequence/seq_*; do
  echo "tracking $seq" >&2
  status=0
  # shellcheck disable=SC2046  # one model path a line, no spaces
  (cd "$seq" && "$bin/pcl_icf_tool" --track frames.txt $(cat tracked_models.txt) -q \
    >poses.jsonl) || status=$?
  # 1: an object had no pose in some frame (the removed one has none while it is away).
  [ "$status" -le 1 ] || { echo "pcl_icf_tool failed on $seq ($status)" >&2; exit 2; }
done
"$bin/pcl_icf_track_score" "$out"/sequence/seq_*
