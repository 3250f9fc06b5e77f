#!/usr/bin/env bash
# The main job: set up (packages + build), then render the default scene with
# the brute-force forward and deferred renderers, print per-pass timings and
# light counts, and write out/<technique>.png and out/<technique>.json.
# Extra arguments go to every `manylights render` call (e.g. --size 1280x720).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/setup.sh
mkdir -p out
for t in forward deferred; do
  echo
  echo "=== $t ==="
  ./build/manylights render --technique "$t" --counts --out "out/$t.png" --stats-json "out/$t.json" "$@"
done
