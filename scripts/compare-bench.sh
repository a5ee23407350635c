#!/usr/bin/env bash
# Runs benchmark scenarios with several tessera binaries taking turns in one run, and prints
# each cell's median frame time per binary and turn side by side, with each binary's change
# against the first (JSON lines under OUT_DIR). With TURNS=2 (the default) each scenario runs
# the binaries in order and then in reverse (before, after, after, before for two), so that a
# clock or temperature drift through the run shows as a difference between a binary's two
# turns rather than between the binaries; TURNS=1 runs them once, in order.
# Usage: scripts/compare-bench.sh OUT_DIR BEFORE_BINARY AFTER_BINARY 'SCENARIO ARGS' ...
#        scripts/compare-bench.sh OUT_DIR BINARY BINARY [BINARY ...] -- 'SCENARIO ARGS' ...
# The first form names the two "before" and "after"; the second names each by its file name
# (which must differ).
# Environment: TURNS (1 or 2), LIMIT (seconds one scenario run may take, default 280), PACK (a
# file: OUT_DIR packed into it as a gzipped tar at the end, for a machine that hands back only
# a few files).
set -uo pipefail
out=${1:?output folder}
shift
binaries=()
labels=()
if printf '%s\n' "$@" | grep -qx -- '--'; then
  while [ "$#" -gt 0 ] && [ "$1" != "--" ]; do
    binaries+=("$1")
    labels+=("$(basename "$1")")
    shift
  done
  shift
else
  binaries=("${1:?before binary}" "${2:?after binary}")
  labels=(before after)
  shift 2
fi
if [ "${#binaries[@]}" -lt 2 ]; then
  echo "compare-bench.sh: two binaries or more to compare" >&2
  exit 2
fi
if [ "$(printf '%s\n' "${labels[@]}" | sort -u | wc -l)" -ne "${#labels[@]}" ]; then
  echo "compare-bench.sh: the binaries' file names must differ: ${labels[*]}" >&2
  exit 2
fi
forward=$(seq 0 $((${#binaries[@]} - 1)))
case ${TURNS:-2} in
  1) order=$forward ;;
  2) order="$forward $(echo "$forward" | tac)" ;;
  *) echo "compare-bench.sh: TURNS is 1 or 2, not '${TURNS}'" >&2; exit 2 ;;
esac
order=$(echo $order)
mkdir -p "$out"
last=${binaries[${#binaries[@]} - 1]}
if ! "$last" info >/dev/null 2>&1 && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
fi
"$last" info > "$out/info.txt" 2>&1
nvidia-smi --query-gpu=name,driver_version,clocks.max.sm --format=csv > "$out/nvidia-smi.csv" 2>&1
date -u +%Y-%m-%dT%H:%M:%SZ > "$out/date.txt"
index=0
for scenario in "$@"; do
  # Numbered, so that one scenario on two data sets keeps both.
  index=$((index + 1))
  name=$index-${scenario%% *}
  turn=0
  for i in $order; do
    turn=$((turn + 1))
    label=${labels[$i]}
    start=$SECONDS
    # shellcheck disable=SC2086
    timeout "${LIMIT:-280}" "${binaries[$i]}" bench $scenario --json "$out/$label-$turn-$name.jsonl" \
      > "$out/$label-$turn-$name.log" 2>&1 \
      || echo "$label $name turn $turn: exit $?" | tee -a "$out/failures.txt"
    echo "$name: $label (turn $turn) in $((SECONDS - start)) s"
  done
done
python3 - "$out" "${labels[*]}" "$order" "$@" <<'PY'
import json, sys, os
out, labels, order, scenarios = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), sys.argv[4:]
def records(path):
    rows = {}
    if not os.path.exists(path):
        return rows
    for line in open(path):
        r = json.loads(line)
        key = (r.get("technique"), r.get("path"), r.get("dataset"), r.get("variant", ""), r.get("width"), r.get("height"))
        stages = {s["stage"]: s["median_ms"] for s in r.get("stages", []) if s["stage"] != "frame-span"}
        ms = list(stages.values())
        # A record may hold its stages and their total (culled frames): count the total once.
        total = max(ms, default=0.0)
        rest = sum(ms) - total
        # The passes' sum, which binaries of every age record; `frame-span` (the whole
        # frame) is newer, and a span against a sum would show what runs between the passes
        # as a change.
        if "frame" in stages:
            rows[key] = stages["frame"]
        else:
            rows[key] = total if len(ms) > 2 and abs(rest - total) <= 0.01 * total else sum(ms)
    return rows
head = f"{'technique':<14} {'path':<10} {'dataset':<40} {'size':<10}"
for n, label in enumerate(labels):
    head += f" {label[:15] + ' ms':>17}" + (f" {'change':>8}" if n else "")
print(head)
for index, scenario in enumerate(scenarios, start=1):
    name = f"{index}-{scenario.split()[0]}"
    turns = {label: [] for label in labels}
    for turn, i in enumerate(order, start=1):
        label = labels[int(i)]
        turns[label].append(records(f"{out}/{label}-{turn}-{name}.jsonl"))
    for key in turns[labels[0]][0]:
        values = [[t[key] for t in turns[label] if key in t] for label in labels]
        if not all(values):
            continue
        t, p, d, v, w, h = key
        row = f"{t:<14} {p:<10} {(d + (f' {v}' if v else ''))[:40]:<40} {w}x{h:<5}"
        first = sum(values[0]) / len(values[0])
        for n, xs in enumerate(values):
            row += f" {' / '.join(f'{x:.3f}' for x in xs):>17}"
            if n:
                mean = sum(xs) / len(xs)
                row += f" {(mean / first - 1) * 100 if first else float('nan'):>+7.1f}%"
        print(row)
PY
if [ -n "${PACK:-}" ]; then
  tar czf "$PACK" -C "$out" .
fi
