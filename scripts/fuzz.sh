#!/usr/bin/env bash
# Coverage-guided fuzzing of the tessera-data loaders with libFuzzer (see docs/FUZZING.md).
#
#   scripts/fuzz.sh TARGET|all SECONDS [LIBFUZZER_ARGS...]
#
# Builds the targets of fuzz/ on the stable toolchain with the instrumentation
# `cargo fuzz build --sanitizer none` uses (plain cargo: cargo-fuzz need not be installed),
# runs each for SECONDS on one core and prints executions and crashes per target. New inputs
# go to fuzz/corpus/TARGET (starting from the committed seeds in fuzz/seeds/TARGET), crashing
# or hanging ones to fuzz/artifacts/TARGET; fuzz/dicts/TARGET.dict, where present, lists the
# format's keywords. Exits non-zero when any target crashed.
#
# Environment: CARGO_TARGET_DIR (default fuzz/target), FUZZ_MAX_LEN (default 16384),
# FUZZ_RSS_MB (default 2048), FUZZ_TIMEOUT (seconds one input may take, default 10).
set -euo pipefail
cd "$(dirname "$0")/.."

usage() {
  echo "usage: $0 TARGET|all SECONDS [LIBFUZZER_ARGS...]" >&2
  echo "targets: $(targets | tr '\n' ' ')" >&2
  exit 2
}
targets() { sed -n 's/^name = "\(.*\)"$/\1/p' fuzz/Cargo.toml | grep -v '^tessera-data-fuzz$'; }

[ $# -ge 2 ] || usage
which=$1
seconds=$2
shift 2
[[ $seconds =~ ^[0-9]+$ ]] || usage
if [ "$which" = all ]; then
  list=$(targets)
else
  targets | grep -qx "$which" || usage
  list=$which
fi

export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$PWD/fuzz/target}
triple=$(rustc -vV | sed -n 's/^host: //p')
# The flags of `cargo fuzz build --sanitizer none` (cargo-fuzz 0.13): SanitizerCoverage for
# libFuzzer, all of them stable rustc options.
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing \
-Cllvm-args=-simplifycfg-branch-fold-threshold=0 -Cllvm-args=-sanitizer-coverage-stack-depth \
-Cdebug-assertions -Ccodegen-units=1"
bins=()
for t in $list; do bins+=(--bin "$t"); done
cargo build --manifest-path fuzz/Cargo.toml --release --target "$triple" \
  --config 'profile.release.debug="line-tables-only"' "${bins[@]}"

# One core per run: the loaders' rayon pools get one thread.
export RAYON_NUM_THREADS=1
failed=0
summary=()
for t in $list; do
  corpus=fuzz/corpus/$t
  artifacts=fuzz/artifacts/$t
  mkdir -p "$corpus" "$artifacts"
  before=$(find "$artifacts" -type f | wc -l)
  dict=()
  [ -f "fuzz/dicts/$t.dict" ] && dict=(-dict="fuzz/dicts/$t.dict")
  log=$(mktemp)
  start=$(date +%s)
  set +e
  "$CARGO_TARGET_DIR/$triple/release/$t" "$corpus" "fuzz/seeds/$t" \
    -max_total_time="$seconds" -timeout="${FUZZ_TIMEOUT:-10}" \
    -rss_limit_mb="${FUZZ_RSS_MB:-2048}" -malloc_limit_mb="${FUZZ_RSS_MB:-2048}" \
    -max_len="${FUZZ_MAX_LEN:-16384}" -artifact_prefix="$artifacts/" \
    -print_final_stats=1 "${dict[@]}" "$@" >"$log" 2>&1
  rc=$?
  set -e
  took=$(($(date +%s) - start))
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  crashes=$(($(find "$artifacts" -type f | wc -l) - before))
  if [ "$rc" -ne 0 ] && [ "$crashes" -eq 0 ]; then crashes=1; fi
  if [ "$crashes" -ne 0 ]; then
    failed=1
    echo "== $t: exit $rc; the end of its log:" >&2
    tail -40 "$log" >&2
    ls "$artifacts" >&2
  fi
  rm -f "$log"
  line=$(printf '%-18s %12s executions %6s s %3s crash(es) corpus %s' "$t" "${runs:-?}" \
    "$took" "$crashes" "$(find "$corpus" -type f | wc -l)")
  echo "$line"
  summary+=("$line")
done
echo "---- summary"
printf '%s\n' "${summary[@]}"
exit $failed
