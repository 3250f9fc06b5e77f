#!/usr/bin/env bash
# Outputs that a refactoring must leave unchanged, captured and compared:
#
#   scripts/golden_outputs.sh capture DIR [BUILD]   renders and benches into DIR
#   scripts/golden_outputs.sh compare OLD NEW       exit 1 on any difference
#
# capture: every technique's render of the default scene as scripts/run.sh
# makes it (PNG, heat map, stats JSON); the Cornell box with voxel cone tracing
# and its reference comparison; the thesis suite's Spaceship Indoor hashed and
# clustered bench over a few frames (needs ../shared/data/thesis-suite).
# compare: PNGs byte by byte, JSON field by field except what measures time or
# names the machine (scripts/lib/compare_json.py says which fields).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"  # inputs by relative paths: results record them as given
usage() { echo "usage: $0 capture DIR [BUILD] | compare OLD NEW" >&2; exit 2; }
[[ $# -ge 2 ]] || usage

capture() {
  local dir bin="${2:-$root/build}/manylights"
  dir="$(mkdir -p "$1" && cd "$1" && pwd)"
  [[ -x "$bin" ]] || { echo "$0: $bin: not built" >&2; exit 2; }
  mkdir -p "$dir"
  for t in $("$bin" techniques | awk '{print $1}'); do
    "$bin" render --technique "$t" --counts --out "$dir/$t.png" --heatmap "$dir/$t-heat.png" \
      --stats-json "$dir/$t.json" >/dev/null
  done
  "$bin" render --scene data/cornell/cornell.gltf --gi vct --gi-reference --size 96x96 \
    --out "$dir/cornell-vct.png" --stats-json "$dir/cornell-vct.json" >/dev/null
  local suite="../shared/data/thesis-suite/scenes/spaceship-indoor"
  if [[ -d "$suite" ]]; then
    "$bin" bench --suite "$suite" --allow-missing-meshes --lights thesis --techniques hashed-deferred,clustered-deferred \
      --param node_size=11.5 --param start_depth=3 --size 160x160 --frames 3:131:64 \
      --json "$dir/thesis-hashed.json" >/dev/null
  else
    echo "$0: no thesis suite beside the checkout; its bench is not captured" >&2
  fi
}

compare() {
  local old="$1" new="$2" status=0 f
  for f in "$old"/*; do
    local name; name="$(basename "$f")"
    if [[ ! -e "$new/$name" ]]; then echo "missing in $new: $name"; status=1; continue; fi
    case "$name" in
      *.png) cmp -s "$f" "$new/$name" || { echo "differs: $name"; status=1; } ;;
      *.json) python3 "$root/scripts/lib/compare_json.py" "$f" "$new/$name" || status=1 ;;
    esac
  done
  [[ $status -eq 0 ]] && echo "golden outputs: $(ls "$old" | wc -l) files equal"
  return $status
}

case "$1" in
  capture) capture "$2" "${3:-}" ;;
  compare) [[ $# -eq 3 ]] || usage; compare "$2" "$3" ;;
  *) usage ;;
esac
