#!/usr/bin/env bash
# Runs benchmark scenarios with two tessera binaries, alternating them per scenario in one run,
# and prints each record's median stage times side by side (JSON lines under OUT_DIR).
# Usage: scripts/compare-bench.sh OUT_DIR BEFORE_BINARY AFTER_BINARY 'SCENARIO ARGS' ...
set -uo pipefail
out=${1:?output folder}; before=${2:?binary}; after=${3:?binary}; shift 3
mkdir -p "$out"
if ! "$after" info >/dev/null 2>&1 && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
"$after" info > "$out/info.txt" 2>&1
date -u +%Y-%m-%dT%H:%M:%SZ > "$out/date.txt"
for scenario in "$@"; do
  name=${scenario%% *}
  for side in before after; do
    bin=$before; [ "$side" = after ] && bin=$after
    # shellcheck disable=SC2086
    timeout 280 "$bin" bench $scenario --json "$out/$side-$name.jsonl" > "$out/$side-$name.log" 2>&1 \
      || echo "$side $name: exit $?" | tee -a "$out/failures.txt"
  done
done
python3 - "$out" "$@" <<'PY'
import json, sys, os
out = sys.argv[1]
def records(path):
    rows = {}
    if not os.path.exists(path):
        return rows
    for line in open(path):
        r = json.loads(line)
        key = (r.get("technique"), r.get("path"), r.get("dataset"), r.get("variant", ""), r.get("width"), r.get("height"))
        ms = [s["median_ms"] for s in r.get("stages", [])]
        # A record may hold its stages and their total (culled frames): count the total once.
        total = max(ms, default=0.0)
        rest = sum(ms) - total
        rows[key] = total if len(ms) > 2 and abs(rest - total) <= 0.01 * total else sum(ms)
    return rows
print(f"{'technique':<14} {'path':<12} {'dataset':<44} {'size':<10} {'before ms':>10} {'after ms':>10} {'change':>8}")
for scenario in sys.argv[2:]:
    name = scenario.split()[0]
    b = records(f"{out}/before-{name}.jsonl"); a = records(f"{out}/after-{name}.jsonl")
    for key in b:
        if key not in a:
            continue
        t, p, d, v, w, h = key
        label = (d + (f" {v}" if v else ""))[:44]
        change = (a[key] / b[key] - 1) * 100 if b[key] else float("nan")
        print(f"{t:<14} {p:<12} {label:<44} {w}x{h:<5} {b[key]:>10.3f} {a[key]:>10.3f} {change:>+7.1f}%")
PY
