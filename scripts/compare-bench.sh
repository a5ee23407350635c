#!/usr/bin/env bash
# Runs benchmark scenarios with two tessera binaries taking turns in one run, and prints each
# cell's median frame time per turn side by side (JSON lines under OUT_DIR). With TURNS=2 (the
# default) each scenario runs before, after, after, before, so that a clock or temperature
# drift through the run shows as a difference between a binary's two turns rather than
# between the binaries; TURNS=1 runs before, after.
# Usage: scripts/compare-bench.sh OUT_DIR BEFORE_BINARY AFTER_BINARY 'SCENARIO ARGS' ...
# Environment: TURNS (1 or 2), LIMIT (seconds one scenario run may take, default 280), PACK (a
# file: OUT_DIR packed into it as a gzipped tar at the end, for a machine that hands back only
# a few files).
set -uo pipefail
out=${1:?output folder}; before=${2:?binary}; after=${3:?binary}; shift 3
turns=${TURNS:-2}
case $turns in
  1) order="before after" ;;
  2) order="before after after before" ;;
  *) echo "compare-bench.sh: TURNS is 1 or 2, not '$turns'" >&2; exit 2 ;;
esac
mkdir -p "$out"
if ! "$after" info >/dev/null 2>&1 && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
"$after" info > "$out/info.txt" 2>&1
nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv > "$out/nvidia-smi.csv" 2>&1
date -u +%Y-%m-%dT%H:%M:%SZ > "$out/date.txt"
index=0
for scenario in "$@"; do
  # Numbered, so that one scenario on two data sets keeps both.
  index=$((index + 1))
  name=$index-${scenario%% *}
  turn=0
  for side in $order; do
    turn=$((turn + 1))
    bin=$before; [ "$side" = after ] && bin=$after
    start=$SECONDS
    # shellcheck disable=SC2086
    timeout "${LIMIT:-280}" "$bin" bench $scenario --json "$out/$side-$turn-$name.jsonl" \
      > "$out/$side-$turn-$name.log" 2>&1 \
      || echo "$side $name turn $turn: exit $?" | tee -a "$out/failures.txt"
    echo "$name: $side (turn $turn) in $((SECONDS - start)) s"
  done
done
python3 - "$out" "$order" "$@" <<'PY'
import json, sys, os
out, order, scenarios = sys.argv[1], sys.argv[2].split(), sys.argv[3:]
def records(path):
    rows = {}
    if not os.path.exists(path):
        return rows
    for line in open(path):
        r = json.loads(line)
        key = (r.get("technique"), r.get("path"), r.get("dataset"), r.get("variant", ""), r.get("width"), r.get("height"))
        stages = {s["stage"]: s["median_ms"] for s in r.get("stages", [])}
        ms = list(stages.values())
        # A record may hold its stages and their total (culled frames): count the total once.
        total = max(ms, default=0.0)
        rest = sum(ms) - total
        # The passes' sum, which binaries of every age record; `frame-span` (the whole
        # frame) is newer, and a span against a sum would show the drain between passes
        # as a change.
        if "frame" in stages:
            rows[key] = stages["frame"]
        else:
            rows[key] = total if len(ms) > 2 and abs(rest - total) <= 0.01 * total else sum(ms)
    return rows
print(f"{'technique':<14} {'path':<10} {'dataset':<40} {'size':<10} {'before ms':>15} {'after ms':>15} {'change':>8}")
for index, scenario in enumerate(scenarios, start=1):
    name = f"{index}-{scenario.split()[0]}"
    turns = {"before": [], "after": []}
    for turn, side in enumerate(order, start=1):
        turns[side].append(records(f"{out}/{side}-{turn}-{name}.jsonl"))
    for key in turns["before"][0]:
        b = [t[key] for t in turns["before"] if key in t]
        a = [t[key] for t in turns["after"] if key in t]
        if not a or not b:
            continue
        t, p, d, v, w, h = key
        label = (d + (f" {v}" if v else ""))[:40]
        mb, ma = sum(b) / len(b), sum(a) / len(a)
        change = (ma / mb - 1) * 100 if mb else float("nan")
        show = lambda xs: " / ".join(f"{x:.3f}" for x in xs)
        print(f"{t:<14} {p:<10} {label:<40} {w}x{h:<5} {show(b):>15} {show(a):>15} {change:>+7.1f}%")
PY
if [ -n "${PACK:-}" ]; then
  tar czf "$PACK" -C "$out" .
fi
