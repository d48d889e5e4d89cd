#!/usr/bin/env bash
# Captures what every command prints and writes, for a byte-for-byte comparison of two
# builds (a refactor must change none of it):
#
#   scripts/outputs.sh OLD_BINARY /tmp/before
#   scripts/outputs.sh target/release/phalanx /tmp/after
#   diff -r /tmp/before /tmp/after
#
# Runs from the checkout on the paper's data: stats (table, json, csv, --wide), check,
# compare (the X-rays against the atlas), coverage, place, history and report; and on every
# rig under ${PHALANX_SHARED:-../shared}/rigs (skipped with a word when absent): audit (text,
# json, --brief), --moves, --fix, deform, deform --fix and rig --replace-fingers. Each run
# keeps its standard output, standard error, exit status and the files it writes. Every run
# works in the same scratch directory, so paths in messages are alike from build to build.
set -uo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 2 ] || { echo "usage: scripts/outputs.sh BINARY OUTDIR" >&2; exit 2; }
bin=$(readlink -f "$1")
final=$(readlink -m "$2")
work=/tmp/phalanx-outputs
exec 9>"$work.lock"
flock 9
rm -rf "$work" "$final"
mkdir -p "$work"
run() {
    local name=$1
    shift
    "$bin" "$@" >"$work/$name.out" 2>"$work/$name.err"
    echo "rc=$?" >>"$work/$name.out"
}
run stats stats
run stats-json stats --format json
run stats-csv stats --format csv
run stats-wide --wide stats
run check check
run compare compare data/measurements.csv data/atlas/measurements.csv
run compare-json compare data/measurements.csv data/atlas/measurements.csv --format json
run coverage coverage --sims 200
run place place --finger index --length 90
run place-hand place --hand thumb=60,index=90,little=70 --format json
run history history
run report report --out "$work/report"
rigs=${PHALANX_SHARED:-../shared}/rigs
if [ -d "$rigs" ]; then
    for f in "$rigs"/*/*.glb "$rigs"/*/*.gltf "$rigs"/*/*.fbx; do
        [ -f "$f" ] || continue
        b=$(basename "$f")
        b=${b%.*}
        side=()
        [ "$b" = mannequiny ] && side=(--side right)
        run "audit-$b" audit "$f"
        run "audit-json-$b" audit "$f" --format json
        run "audit-brief-$b" audit "$f" --brief
        run "moves-$b" audit "$f" --moves "$work/moves-$b.csv"
        run "fix-$b" audit "$f" --fix "$work/fixed-$b.glb"
        run "deform-$b" deform "$f" "${side[@]}"
        run "deform-fix-$b" deform "$f" "${side[@]}" --fix
        run "rig-$b" rig "$f" "${side[@]}" --replace-fingers --out "$work/rigged-$b.glb"
    done
else
    echo "outputs: $rigs is absent, so no rig was run" >&2
fi
mv "$work" "$final"
echo "outputs: $(find "$final" -type f | wc -l) files in $final"
