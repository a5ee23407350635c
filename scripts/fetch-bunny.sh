#!/usr/bin/env bash
# The tetrahedralized Stanford bunny the real-data tests render (DESIGN §8): the surface from
# the npm package `bunny` (1,839 vertices, 3,674 triangles), tetrahedralized by Debian's
# `tetgen` with quality bound 1.414. Writes bunny.off and bunny.1.{node,ele,face} under
# ${TESSERA_DATA:-$HOME/.cache/tessera/data}/bunny; prints a note and succeeds when npm, node
# or tetgen is missing, so that the tests that need it skip.
set -euo pipefail

dir="${TESSERA_DATA:-${XDG_CACHE_HOME:-$HOME/.cache}/tessera/data}/bunny"
[ -s "$dir/bunny.1.ele" ] && exit 0
for tool in npm node tetgen; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "note: without $tool the bunny tests are skipped" >&2
    exit 0
  fi
done
mkdir -p "$dir"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if ! (cd "$work" && npm pack bunny --silent >/dev/null 2>&1 && tar xzf bunny-*.tgz); then
  echo "note: 'npm pack bunny' failed; the bunny tests are skipped" >&2
  exit 0
fi
# The package is a CommonJS module of vertex positions and triangle cells.
node -e '
  const b = require(process.argv[1]);
  const lines = ["OFF", `${b.positions.length} ${b.cells.length} 0`];
  for (const p of b.positions) lines.push(p.join(" "));
  for (const c of b.cells) lines.push(`3 ${c.join(" ")}`);
  require("fs").writeFileSync(process.argv[2], lines.join("\n") + "\n");
' "$work/package/index.js" "$dir/bunny.off"
# -p: a piecewise linear complex from the surface; -q1.414: radius-edge ratio bound; -Q quiet.
if ! tetgen -pq1.414Q "$dir/bunny.off" >/dev/null; then
  echo "note: tetgen failed on the bunny; its tests are skipped" >&2
  rm -f "$dir"/bunny.1.*
fi
