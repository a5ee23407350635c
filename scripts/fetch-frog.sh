#!/usr/bin/env bash
# The frog tissue labels the real-data tests render (DESIGN §8): 500×470×136 uint8 labels with
# 1 × 1 × 1.5 spacing, a VTK XML ImageData file shipped inside PyPI's `pyvista` wheel (only the
# wheel is downloaded, nothing is installed). Writes frog_tissues.vti under
# ${TESSERA_DATA:-$HOME/.cache/tessera/data}/frog; prints a note and succeeds when python3 or
# PyPI is unavailable, so that the tests that need it skip.
set -euo pipefail

dir="${TESSERA_DATA:-${XDG_CACHE_HOME:-$HOME/.cache}/tessera/data}/frog"
out="$dir/frog_tissues.vti"
[ -s "$out" ] && exit 0
if ! command -v python3 >/dev/null 2>&1; then
  echo "note: without python3 the frog tests are skipped" >&2
  exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# pip from a throw-away virtual environment (Debian's python3 may come without it); a fixed
# release, so the file the tests check is always the same.
if ! python3 -m venv "$work/venv" >/dev/null 2>&1 \
   || ! "$work/venv/bin/pip" download -q --no-deps --dest "$work" pyvista==0.49.2 >/dev/null 2>&1; then
  echo "note: could not download the pyvista wheel from PyPI; the frog tests are skipped" >&2
  exit 0
fi
mkdir -p "$dir"
python3 - "$work" "$out" <<'PY'
import glob, sys, zipfile
wheel = glob.glob(f"{sys.argv[1]}/pyvista-*.whl")[0]
with zipfile.ZipFile(wheel) as z, open(sys.argv[2] + ".part", "wb") as f:
    f.write(z.read("pyvista/examples/frog_tissues.vti"))
PY
mv "$out.part" "$out"
