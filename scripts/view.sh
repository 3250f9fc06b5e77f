#!/usr/bin/env bash
# Opens the interactive viewer on the default scene (setup and build first).
# Extra arguments go to `manylights view` (e.g. --technique tiled-forward --lights 4096).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/setup.sh
exec ./build/manylights view "$@"
