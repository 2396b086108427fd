#!/usr/bin/env bash
# Builds the libFuzzer targets (the "fuzz" preset: clang, ASan+UBSan) and runs each for
# FUZZ_SECONDS (default 60). Exits non-zero when a target finds a crash, a hang, a leak or a
# failed check; the input is kept under build/fuzz/artifacts/<target>/.
#
#   scripts/fuzz.sh                          every target, 60 s each
#   FUZZ_SECONDS=3600 scripts/fuzz.sh fuzz_scene_pcd fuzz_pipeline
#   FUZZ_JOBS=2 ...                          libFuzzer workers per target (default 1)
#   FUZZ_PARALLEL=1 ...                      targets at a time (default: nproc)
#   FUZZ_RSS_MB=4096 ...                     memory limit per worker (default 2048)
#
# New inputs that reach new code go to build/fuzz/corpus/<target>/ (kept between runs); the
# committed seeds in fuzz/corpus/<target>/ are only read. See doc/HOSTILE_INPUTS.md.
set -euo pipefail
cd "$(dirname "$0")/.."
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
FUZZ_JOBS=${FUZZ_JOBS:-1}
ALL=(fuzz_scene_pcd fuzz_scene_ply fuzz_scene_xyz fuzz_mesh_ply fuzz_mesh_obj fuzz_mesh_stl
     fuzz_mesh_vtk fuzz_pipeline)
# Each target once: two runs of one target would share its log and result file.
mapfile -t TARGETS < <(printf '%s\n' "${@:-${ALL[@]}}" | awk '!seen[$0]++')

start=$(date +%s)
nice cmake --preset fuzz >/dev/null
nice cmake --build --preset fuzz -j "${JOBS:-$(nproc)}"
echo "== fuzz: built in $(( $(date +%s) - start )) s"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# One target: its run, then its summary or its failure into build/fuzz/<target>.result.
fuzzOne() {
  local t=$1
  local work=build/fuzz/corpus/$t
  local artifacts=build/fuzz/artifacts/$t/
  mkdir -p "$work" "$artifacts"
  local log=build/fuzz/$t.log result=build/fuzz/$t.result
  local args=(-max_total_time="$FUZZ_SECONDS" -rss_limit_mb="${FUZZ_RSS_MB:-2048}" -timeout=10
              -print_final_stats=1 -artifact_prefix="$artifacts")
  # The pipeline keeps SampleConsensus models in a process-wide cache, so inputs allocate more
  # than they free and libFuzzer would scan the heap for leaks after each (half its time);
  # ASan's leak check at exit stays on.
  if [ "$t" = fuzz_pipeline ]; then
    args+=(-detect_leaks=0)
  fi
  if [ "$FUZZ_JOBS" -gt 1 ]; then
    args+=(-fork="$FUZZ_JOBS" -ignore_crashes=0)
  fi
  if nice "build/fuzz/fuzz/$t" "${args[@]}" "$work" "fuzz/corpus/$t" >"$log" 2>&1; then
    { echo "PASSED"
      echo "== fuzz: $t for ${FUZZ_SECONDS} s"
      grep -E '^stat::number_of_executed_units|^#[0-9]+[[:space:]]+DONE' "$log" | tail -2 || true
    } >"$result"
  else
    { echo "fuzz: $t FAILED (log: $log, input: $(ls -t "$artifacts" | head -1))"
      grep -E 'ERROR|SUMMARY|check failed|deadly|timeout|leak' "$log" | head -5 || true
    } >"$result"
  fi
}

# FUZZ_PARALLEL targets at a time (default: one per core; each target is one process), each
# for the full FUZZ_SECONDS: on 2 cores the 8 targets take 4 minutes instead of 8.
FUZZ_PARALLEL=${FUZZ_PARALLEL:-$(nproc)}
# A stopped script stops its fuzzers too.
trap 'jobs -p | xargs -r kill 2>/dev/null' EXIT
running=0
for t in "${TARGETS[@]}"; do
  rm -f "build/fuzz/$t.result"
  fuzzOne "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$FUZZ_PARALLEL" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait
# A target passed only when its result says so in its first line; anything else (a failure,
# no result, a result cut short) fails it.
failed=()
for t in "${TARGETS[@]}"; do
  result=build/fuzz/$t.result
  if [ "$(head -1 "$result" 2>/dev/null)" = PASSED ]; then
    tail -n +2 "$result"
  else
    cat "$result" >&2 2>/dev/null || true
    echo "fuzz: $t did not pass" >&2
    failed+=("$t")
  fi
done
echo "== fuzz: done in $(( $(date +%s) - start )) s"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: failing targets: ${failed[*]}" >&2
  exit 1
fi
