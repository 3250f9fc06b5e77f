#!/usr/bin/env bash
# Takes the README's viewer screenshot (docs/img/viewer.png) under Xvfb: the
# default scene, tiled deferred, with the panel showing, the window as a user
# sees it. Needs a built ./build/manylights and xvfb-run (Debian: xvfb).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
out="${1:-docs/img/viewer.png}"
mkdir -p "$(dirname "$out")"
script="$(mktemp --suffix=.json)"
trap 'rm -f "$script"' EXIT
cat >"$script" <<JSON
[{"technique": "tiled-deferred"}, {"camera_frame": 0}, {"wait": 3},
 {"counts": true}, {"wait": 2}, {"screenshot_window": "$out"}, {"wait": 1}]
JSON
xvfb-run -a -s '-screen 0 1280x800x24' ./build/manylights view --size 1024x600 --script "$script"
