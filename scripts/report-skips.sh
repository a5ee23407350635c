#!/usr/bin/env bash
# Prints the tests (or parts of tests) that were skipped, with the reason each gave.
set -euo pipefail
log=${1:?skip log}
if [ -s "$log" ]; then
  echo "skipped: $(wc -l < "$log") test part(s) this device or machine cannot run:"
  sed 's/^/  /' "$log"
else
  echo "skipped: none"
fi
