#!/usr/bin/env bash
# Runs the benchmark set of docs/BENCHMARKS.md on a GPU machine: device facts, then each
# scenario appended as JSON lines to $1/bench.jsonl, with a table per scenario on stdout.
# Usage: scripts/gpu-bench.sh OUT_DIR [TESSERA_BINARY]
set -uo pipefail
out=${1:?output folder}
bin=${2:-target/release/tessera}
mkdir -p "$out"
if ! "$bin" info >/dev/null 2>&1 && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
"$bin" info | tee "$out/info.txt"
"$bin" info --json > "$out/info.json"
nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv > "$out/nvidia-smi.csv" 2>&1
date -u +%Y-%m-%dT%H:%M:%SZ > "$out/date.txt"
for scenario in pipeline-throughput raymarch minmax-build; do
  echo "== $scenario"
  timeout 300 "$bin" bench "$scenario" --json "$out/bench.jsonl" 2>&1 | tee "$out/$scenario.txt"
done
