#!/usr/bin/env bash
# Runs the benchmark set of docs/BENCHMARKS.md on a GPU machine with the settling warm-up and
# `--repeat` (cells whose medians move by more than 3 % between the runs are listed): device
# facts, then each scenario appended as JSON lines to OUT/bench.jsonl (its printed table in
# OUT/SCENARIO.txt), then the plots (when matplotlib is there) and a one-line-per-cell summary;
# where nvidia-smi is, the GPU's clocks through the run in OUT/clocks.csv.
# The set is split in seven parts (below), for machines that run a command at most ten
# minutes; no part = all of them. The part `direct` (only when named) times `direct`'s
# candidates on the head phantom of DIRECT_SIZE (default 256) cubed: each draw with the hidden
# side drawn again, and the compute frame with each of the rasterizer's ways.
# Usage: scripts/gpu-bench.sh OUT_DIR [TESSERA_BINARY] [PART]
# PART: volumes, isosurface, iso-sweep, surfaces, meshes, param, growth or direct.
# Environment: REPEAT (default 2), FRAMES (default 50), SCANS (a folder holding ch2.nii.gz),
# EXTRA (more flags for every scenario, e.g. --quick for a smoke run on a CPU driver), WARM
# (0: no throw-away run before each scenario), PACK (a file: the output folder packed into it
# as a gzipped tar at the end, for a machine that hands back only a few files).
set -uo pipefail
out=${1:?output folder}
bin=${2:-target/release/tessera}
part=${3:-all}
case $part in
  all | volumes | isosurface | iso-sweep | surfaces | meshes | param | growth | direct) ;;
  *) echo "gpu-bench.sh: unknown part '$part' (volumes, isosurface, iso-sweep, surfaces, meshes, param, growth, direct or none)" >&2; exit 2 ;;
esac
[ -x "$bin" ] || { echo "gpu-bench.sh: no tessera binary at $bin" >&2; exit 2; }
repeat=${REPEAT:-2}
frames=${FRAMES:-50}
read -r -a extra <<< "${EXTRA:-}"
mkdir -p "$out"
if ! "$bin" info >/dev/null 2>&1 && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
"$bin" info > "$out/info.txt"
"$bin" info --json > "$out/info.json"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv > "$out/nvidia-smi.csv" 2>&1
date -u +%Y-%m-%dT%H:%M:%SZ >> "$out/date.txt"
# The GPU's clocks, power state and load through the run, read five times a second (nothing is
# set), to line up with the records' unix_time_s: whether a slow cell met a slow card.
if command -v nvidia-smi > /dev/null; then
  nvidia-smi --query-gpu=timestamp,clocks.sm,clocks.mem,pstate,power.draw,utilization.gpu \
    --format=csv -lms 200 >> "$out/clocks.csv" 2> /dev/null &
  clock_log=$!
  trap 'kill "$clock_log" 2> /dev/null' EXIT
fi

# One scenario: NAME SECONDS ARGS…; its exit status is kept in OUT/status.txt. Unless WARM=0,
# a throw-away --quick run of the scenario comes first: on the H200 the first process to run a
# freshly built pipeline measured it up to 3.4× slow though its warm-up had settled, and a
# second process did not (docs/BENCHMARKS.md, run 57).
run() {
  local name=$1 limit=$2
  shift 2
  local start=$SECONDS
  if [ "${WARM:-1}" != 0 ]; then
    timeout 60 "$bin" bench "$@" "${extra[@]}" --quick > /dev/null 2>&1
  fi
  timeout "$limit" "$bin" bench "$@" "${extra[@]}" --repeat "$repeat" --json "$out/bench.jsonl" \
    > "$out/$name.txt" 2>&1
  local status=$?
  echo "$name exit $status after $((SECONDS - start)) s" | tee -a "$out/status.txt"
  grep -A30 "moved by more than" "$out/$name.txt" | head -20
}

# The parts, each sized to run within a 10-minute command with REPEAT=1 by what runs 104-105
# took (seconds, with the throw-away runs): volumes 118, surfaces 155 (stereo 129 of it), and
# interval 95.
# Where those runs' limits cut a scenario (isosurface and iso-sweep at 1024^3 after 159 and
# 160 s, shell at its 10.4 M-tet box after 185 s, param after 131 s), it has a part of its own
# and a limit just under ten minutes; their whole durations are not measured yet.
in_part() {
  [ "$part" = all ] || [ "$part" = "$1" ]
}
if in_part volumes; then
  run pipeline-throughput 60 pipeline-throughput --frames "$frames"
  run raymarch 60 raymarch --frames "$frames"
  run minmax-build 60 minmax-build --frames "$frames"
  run time-varying 120 time-varying --frames 30
fi
if in_part isosurface; then
  run isosurface 570 isosurface --frames "$frames"
fi
if in_part iso-sweep; then
  run iso-sweep 570 iso-sweep --sizes 3840x2160 --frames "$frames"
fi
if in_part surfaces; then
  run extraction 90 extraction --paths compute --frames "$frames"
  if [ -n "${SCANS:-}" ] && [ -f "$SCANS/ch2.nii.gz" ]; then
    run extraction-ch2 40 extraction --paths compute --data "$SCANS/ch2.nii.gz" --frames "$frames"
  fi
  run stereo 240 stereo --frames 30
fi
if in_part meshes; then
  run interval 150 interval --paths compute --frames 20 --warmup 3 --max-warmup 40
  run shell 420 shell --frames 40 --warmup 10 --max-warmup 60
fi
if in_part param; then
  run param 570 param --frames 30
fi
if in_part growth; then
  run growth 570 growth --frames 30
fi
if [ "$part" = direct ]; then
  head="procedural:head:${DIRECT_SIZE:-256}:uint8"
  run direct-hidden-side 280 isosurface --data "$head" --sizes 1280x720,3840x2160 \
    --frames "$frames" --variants hidden-side
  run direct-ablations 280 isosurface --data "$head" --sizes 1280x720,3840x2160 \
    --paths compute --frames "$frames" --ablations
fi

if [ -n "${clock_log:-}" ]; then
  kill "$clock_log" 2> /dev/null
fi
python3 "$(dirname "$0")/plot_bench.py" "$out" "$out/bench.jsonl" 2>/dev/null \
  || echo "(no plots: matplotlib missing)"
python3 - "$out/bench.jsonl" <<'PY'
import json, sys
for line in open(sys.argv[1]):
    r = json.loads(line)
    if r.get("repeat", 0):
        continue
    stages = {s["stage"]: s["median_ms"] for s in r["stages"]}
    frame = stages.get("frame-span", stages.get("frame", r["stages"][-1]["median_ms"]))
    size = f'{r["width"]}x{r["height"]}' if r["width"] else "-"
    print(f'{r["scenario"][:12]:12} {r["technique"][:12]:12} {r["path"][:8]:8} '
          f'{r.get("variant", "")[:42]:42} {r["dataset"][:28]:28} {size:9} {frame:9.3f} ms')
PY
if [ -n "${PACK:-}" ]; then
  tar czf "$PACK" -C "$out" .
fi
