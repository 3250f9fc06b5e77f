#!/bin/bash
# render --gi vct frame medians with static lights and with moving lights
# (--animate), BEFORE (a manylights binary from before the volume was reused:
# every frame updated) against AFTER (default build/manylights), alternating
# binary by binary within each case, ROUNDS rounds.
# Usage: BEFORE=/path/to/old/manylights results/vct/reuse.sh > out.txt
# VCT: extra --gi vct flags (default none: 64^3, 4 levels, isotropic).
cd "$(dirname "$0")/../.." || exit 1
BEFORE=${BEFORE:?set BEFORE to the old manylights binary}
AFTER=${AFTER:-build/manylights}
OUT=${OUT:-$(mktemp -d)}
ROUNDS=${ROUNDS:-2}
FRAMES=${FRAMES:-20}
VCT=${VCT:-}
echo "vct flags: ${VCT:-(defaults)}"
echo "uptime start: $(uptime)"
printf "%-5s %-8s %-13s %-6s %8s %8s %8s %8s %8s %8s\n" round scene lights binary frame_ms update_ms trace_ms updates reused moved
for round in $(seq "$ROUNDS"); do
  for scene in default cornell; do
    S=""; A=0.01
    if [ $scene = cornell ]; then
      S="--scene data/cornell/cornell.gltf --lights data/cornell/lights.json --camera data/cornell/camera.json"
      A=0.25  # 0.01 of 4 lights rounds to none
    fi
    for anim in static "animate-$A"; do
      F=""; [ "$anim" != static ] && F="--animate $A"
      for which in before after; do
        if [ $which = before ]; then B=$BEFORE; else B=$AFTER; fi
        base=$OUT/$round-$scene-$anim-$which
        $B render $S --gi vct $VCT --technique hashed-deferred --size 320x180 --frames "$FRAMES" --warmup 1 $F \
          --stats-json "$base.json" > "$base.txt" 2>&1 || { echo "FAILED $base.txt"; tail -3 "$base.txt"; continue; }
        python3 - "$base.json" "$round" "$scene" "$anim" "$which" "$base.txt" <<'PY'
import json, re, sys
j = json.load(open(sys.argv[1])); p = j["passes"]
upd = sum(p.get(k, 0.0) for k in ("vct-voxelize", "vct-lists", "vct-inject", "vct-mips", "vct-textures"))
trace = p.get("vct-trace", 0.0) + p.get("vct-upsample", 0.0)
m = re.search(r"animate: (\d+) of", open(sys.argv[6]).read())
print("%-5s %-8s %-13s %-6s %8.1f %8.1f %8.1f %8s %8s %8s" % (sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5],
      j["frame_host_ms"], upd, trace, j.get("vct_updates"), j.get("vct_reused", "-"), m.group(1) if m else 0))
PY
      done
    done
  done
  echo "uptime after round $round: $(uptime)"
done
