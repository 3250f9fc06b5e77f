#!/bin/bash
# vct-lists per animated frame: BEFORE (a manylights binary built from the
# commit before the incremental lists, every frame rebuilt them) against
# AFTER (default build/manylights), alternating case by case in one run.
# Usage: BEFORE=/path/to/old/manylights results/vct/lists-animated.sh > out.txt
cd "$(dirname "$0")/../.." || exit 1
BEFORE=${BEFORE:?set BEFORE to the old manylights binary}
AFTER=${AFTER:-build/manylights}
OUT=${OUT:-$(mktemp -d)}
echo "uptime start: $(uptime)"
for scene in cornell default; do
  if [ $scene = cornell ]; then S="--scene data/cornell/cornell.gltf --camera data/cornell/camera.json"; else S=""; fi
  for n in 1000 10000; do
    for f in 0.01 0.1; do
      for which in before after; do
        if [ $which = before ]; then B=$BEFORE; else B=$AFTER; fi
        log=$OUT/$scene-$n-$f-$which.txt
        $B render $S --lights $n --gi vct --voxels 64 --levels 4 --anisotropic --technique hashed-deferred \
          --size 320x180 --frames 7 --warmup 1 --animate $f --stats-json $OUT/$scene-$n-$f-$which.json \
          --out $OUT/$scene-$n-$f-$which.png > $log 2>&1 || { echo "FAILED $log"; tail -3 $log; }
        lists=$(awk '$1=="vct-lists"{print $2}' $log); inject=$(awk '$1=="vct-inject"{print $2}' $log)
        up=$(grep -o "updates uploading [0-9]* bytes each (mean) of [0-9]*" $log)
        echo "$scene $n $f $which vct-lists $lists vct-inject $inject $up $(grep -o '[0-9]* of [0-9]* lights move' $log)"
      done
    done
  done
done
echo "uptime end: $(uptime)"
