#!/usr/bin/env bash
# The main job: set up (packages + build), then render the default scene with
# every registered technique (brute-force forward/deferred first, the
# reference), print per-pass timings and light counts, and write
# out/<technique>.png, out/<technique>-heat.png and out/<technique>.json.
# Extra arguments go to every `manylights render` call (e.g. --size 1280x720).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
scripts/setup.sh
mkdir -p out
for t in $(./build/manylights techniques | awk '{print $1}'); do
  echo
  echo "=== $t ==="
  ./build/manylights render --technique "$t" --counts --out "out/$t.png" --heatmap "out/$t-heat.png" \
    --stats-json "out/$t.json" "$@"
done
echo
echo "summary (640x360 unless --size was given):"
python3 - <<'PY'
import json, glob
rows = []
for f in sorted(glob.glob("out/*.json")):
    j = json.load(open(f))
    if "technique" not in j:
        continue
    px = j["light_evaluations"] / max(1, j["covered_pixels"])
    rows.append((j["technique"], j["frame_host_ms"], px, j["light_evaluations"] / max(1, j["lower_bound"])))
print("%-20s %12s %14s %10s" % ("technique", "frame ms", "evals/pixel", "x bound"))
for r in rows:
    print("%-20s %12.1f %14.2f %10.2f" % r)
PY
