#!/usr/bin/env bash
# SH coefficients of a real diffusion MRI scan for the glyph tests (DESIGN §8): DIPY's
# small_64D, fitted by scripts/fit-dwi-sh.py in a private virtual environment with dipy and
# nibabel from PyPI. Writes ${TESSERA_DATA:-$HOME/.cache/tessera/data}/dwi/small_64D_csa8.nii.gz;
# prints a note and succeeds when python3 or PyPI is unavailable, so that the tests skip.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
dir="${TESSERA_DATA:-${XDG_CACHE_HOME:-$HOME/.cache}/tessera/data}/dwi"
out="$dir/small_64D_csa8.nii.gz"
[ -s "$out" ] && exit 0
if ! command -v python3 >/dev/null 2>&1; then
  echo "note: without python3 the diffusion glyph tests are skipped" >&2
  exit 0
fi
mkdir -p "$dir"
venv="$dir/venv"
if ! { [ -x "$venv/bin/python" ] || python3 -m venv "$venv" >/dev/null 2>&1; } \
   || ! "$venv/bin/pip" install -q dipy nibabel >/dev/null 2>&1; then
  echo "note: could not install dipy from PyPI (python3-venv missing?); the diffusion glyph tests are skipped" >&2
  rm -rf "$venv"
  exit 0
fi
"$venv/bin/python" "$here/fit-dwi-sh.py" "$out" >/dev/null 2>&1 \
  || { echo "note: fitting small_64D failed; the diffusion glyph tests are skipped" >&2; rm -f "$out"; }
