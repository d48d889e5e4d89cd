#!/usr/bin/env bash
# Times the release binary on the workloads of issue 6 and prints a Markdown
# table of wall time and peak memory (/usr/bin/time -v): first phalanx against the
# NumPy peer (bench/peer.py, the same statistics) at 1k, 10k and 100k X-rays in the
# same run, then the report at every size from the paper's 5 X-rays to 100,000, then
# how the cost grows with X-rays and resamples.
# Then `phalanx rig` (fingers found, placed and weighted) on the largest shared rig and a
# 50,000-triangle hand, and `audit --fix` on the GDQuest mannequin. Last, the criterion
# benchmarks of the hot paths (benches/kernels.rs: the bootstrap kernel, the loader, the
# fingers found on a skin).
# Usage: bench/run.sh [RUNS]   (default 3; best run kept). BENCH_ONLY=rig runs only the
# rig section, BENCH_ONLY=kernels only the criterion benchmarks. The peer runs in a virtual
# environment, target/bench-venv, made here the first time with bench/requirements.txt
# (numpy and scipy); where it cannot be made (no python3 or no registry) its rows are
# skipped with the reason.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-3}
only=${BENCH_ONLY:-}

# The criterion benchmarks (benches/kernels.rs), their estimates as criterion prints them.
kernels_section() {
    echo "Kernels (criterion, \`cargo bench --bench kernels\`):"
    echo
    echo '```'
    cargo bench -q --bench kernels 2>&1 | grep -E '^[a-z_]+/|time:' || true
    echo '```'
    echo
}
case "$only" in
    "" | rig | kernels) ;;
    *)
        echo "bench: BENCH_ONLY=$only: give rig or kernels, or leave it unset for every section" >&2
        exit 2
        ;;
esac
if [ "$only" = kernels ]; then
    kernels_section
    exit 0
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

if [ ! -x /usr/bin/time ]; then
    echo "bench: /usr/bin/time is missing (Debian package 'time')" >&2
    exit 1
fi
cargo build --release -q
cargo build --release -q --example tube_hand
bin=target/release/phalanx
# A synthetic skinned right hand of about 30,000 triangles (32 vertices per ring, a ring every 1.44 mm).
target/release/examples/tube_hand "$work/hand30k-right.glb" right 32 1.44 0 2> /dev/null
# And of about 50,000 (50,016 triangles: a ring every 0.865 mm).
target/release/examples/tube_hand "$work/hand50k-right.glb" right 32 0.865 0 2> /dev/null

if [ -z "$only" ]; then
    "$bin" synth --xrays 1000 --seed 1 --out "$work/x1k.csv"
    "$bin" synth --xrays 10000 --seed 1 --out "$work/x10k.csv"
    "$bin" synth --xrays 100000 --seed 1 --out "$work/x100k.csv"
    for n in 10 50 200 2500 5000; do "$bin" synth --xrays "$n" --seed 1 --out "$work/x$n.csv"; done
fi

# measure LABEL TARGET -- COMMAND...: best wall time and its peak RSS over $runs runs.
measure() {
    local label=$1 target=$2
    shift 3
    local best_s="" best_kb=""
    for _ in $(seq "$runs"); do
        /usr/bin/time -v -o "$work/time.txt" "$@" > /dev/null 2> "$work/stderr.txt"
        local wall kb s
        wall=$(grep "Elapsed (wall clock)" "$work/time.txt" | awk '{print $NF}')
        kb=$(grep "Maximum resident set size" "$work/time.txt" | awk '{print $NF}')
        s=$(echo "$wall" | awk -F: '{ if (NF == 3) print $1*3600 + $2*60 + $3; else print $1*60 + $2 }')
        if [ -z "$best_s" ] || awk -v a="$s" -v b="$best_s" 'BEGIN { exit !(a < b) }'; then
            best_s=$s
            best_kb=$kb
        fi
    done
    last_s=$best_s
    last_mb=$(echo "$best_kb" | awk '{printf "%.1f", $1/1024}')
    if [ -z "${silent:-}" ]; then
        printf '| %s | %s | %.3f s | %s MB |\n' "$label" "$target" "$best_s" "$last_mb"
    fi
}

# `phalanx rig` (see the header), each rig's fingers placed anew (--replace-fingers: every
# hand here has finger bones), and `audit --fix` on the mannequin. The shared rigs' rows
# are skipped with the reason when ../shared/rigs is not there.
rig_section() {
    echo "Rigging (\`phalanx rig\`: the fingers found on the skin, the joints placed, the skin"
    echo "weighted, the copy written, read back and audited) and the mannequin's fix:"
    echo
    echo "| workload | target | wall time | peak memory |"
    echo "|---|---|---|---|"
    measure "rig --replace-fingers, 50,000-triangle hand (tube_hand right 32 0.865 0)" "< 1 s" -- \
        "$bin" rig "$work/hand50k-right.glb" --replace-fingers --out "$work/rig50k.glb" --force
    local shared=../shared/rigs
    if [ ! -d "$shared" ]; then
        echo
        echo "(the shared rigs' rows skipped: $shared is not there)"
        echo
        return
    fi
    # The largest shared rig: the GDQuest mannequin (a body and two hands, 13,832
    # triangles), its right hand; the largest hand alone: the SteamVR right glove (FBX,
    # 4,900 triangles).
    local mannequin=$shared/gdquest-mannequiny/mannequiny.glb glove=$shared/steamvr-gloves/vr_glove_model.fbx
    local f
    for f in "$mannequin" "$glove"; do
        if [ ! -f "$f" ]; then
            echo
            echo "(the shared rigs' rows skipped: $f is not there)"
            echo
            return
        fi
    done
    measure "rig --replace-fingers --side right, GDQuest mannequin (body, 13,832 triangles)" "< 1 s" -- \
        "$bin" rig "$mannequin" --replace-fingers --side right --out "$work/rig-mannequin.glb" --force
    measure "rig --replace-fingers, FBX (SteamVR right glove, 4,900 triangles)" "< 1 s" -- \
        "$bin" rig "$glove" --replace-fingers --out "$work/rig-glove.glb" --force
    measure "audit --fix, GDQuest mannequin" "< 0.5 s" -- \
        "$bin" audit "$mannequin" --fix "$work/fixed-mannequin.glb" --force
    echo
}

echo "Machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'); $(uname -sr); $($bin --version)"
echo "Date: $(date -u +%Y-%m-%d); best of $runs runs; 10,000 resamples unless noted"
echo
if [ "$only" = rig ]; then
    rig_section
    exit 0
fi

# The NumPy peer's own Python, with the pinned numpy and scipy; what venv and pip
# printed is kept for the reason when the peer has to be skipped.
venv=target/bench-venv
py=$venv/bin/python3
peer_ready() { [ -x "$py" ] && "$py" -c "import numpy, scipy" 2> /dev/null; }
if ! peer_ready; then
    { python3 -m venv "$venv" && "$py" -m pip install -q -r bench/requirements.txt; } > "$work/venv.txt" 2>&1 || true
fi

if peer_ready; then
    echo "phalanx against the NumPy peer (bench/peer.py: chunked index matrices, bincount, BLAS"
    echo "matrix product; $("$py" -c 'import numpy, scipy; print("numpy", numpy.__version__, "scipy", scipy.__version__)')),"
    echo "stats --format json, 10,000 resamples; the ratio is the peer's wall time over phalanx's:"
    echo
    echo "| workload | target | wall time | peak memory | ratio |"
    echo "|---|---|---|---|---|"
    for size in 1k 10k 100k; do
        case $size in
            1k) target="-" ;;
            10k) target="60x the peer" ;;
            100k) target="3 s / 250 MB" ;;
        esac
        silent=1 measure "" "" -- "$py" bench/peer.py "$work/x$size.csv"
        printf '| NumPy peer, %s X-rays | | %.3f s | %s MB | 1x |\n' "$size" "$last_s" "$last_mb"
        peer_s=$last_s
        silent=1 measure "" "" -- "$bin" stats --data "$work/x$size.csv" --format json
        printf '| phalanx, %s X-rays | %s | %.3f s | %s MB | %s |\n' "$size" "$target" "$last_s" "$last_mb" \
            "$(awk -v a="$peer_s" -v b="$last_s" 'BEGIN { printf "%.1fx faster", a / b }')"
    done
    echo
else
    echo "(NumPy peer skipped: could not make $venv with bench/requirements.txt: $(tail -n 1 "$work/venv.txt" 2> /dev/null))"
    echo
fi
echo "The report (all formats and plots) at every size: the paper's data with the atlas and"
echo "real-rig sections, then synthetic data of n X-rays (coverage simulated up to 200 X-rays):"
echo
echo "| workload | target | wall time | peak memory |"
echo "|---|---|---|---|"
measure "report, paper data (5 X-rays), with the atlas and the real rig" "0.6 s" -- "$bin" report --out "$work/r5"
for size in 10 50 200 1k 10k 100k; do
    measure "report, $size X-rays" "2 s" -- "$bin" report --data "$work/x$size.csv" --out "$work/r$size"
done
echo
echo "| workload | target | wall time | peak memory |"
echo "|---|---|---|---|"
measure "import the atlas (910 radiographs, atlas37)" "import + compare 100 ms" -- "$bin" import data/atlas/landmarks.csv --layout atlas37 --source "Digital Hand Atlas" --out "$work/atlas.csv" --force
measure "compare the paper with the atlas" "import + compare 100 ms" -- "$bin" compare data/measurements.csv data/atlas/measurements.csv
measure "compare the paper with a published table (B&K 2010, atlas correlations)" "100 ms" -- "$bin" compare data/measurements.csv data/literature/buryanov-kotiuk-2010.csv
measure "place --reference a published table (every finger)" "100 ms" -- "$bin" place --hand thumb=5,index=8,middle=9,ring=8.5,little=6.5 --reference data/literature/buryanov-kotiuk-2010.csv
measure "paper data, full report without the published-measurements section" "-" -- "$bin" report --out "$work/r2" --literature "$work/no-such-table.csv"
measure "rig audit (docs/examples/hand.glb)" "-" -- "$bin" audit docs/examples/hand.glb
measure "rig audit --fix (docs/examples/hand.glb)" "-" -- "$bin" audit docs/examples/hand.glb --fix "$work/fixed.glb" --force
# The SteamVR right glove (binary FBX 7500, 3,032 vertices), when ../shared has it.
glove=../shared/rigs/steamvr-gloves/vr_glove_model.fbx
if [ -f "$glove" ]; then
    measure "rig audit, FBX (SteamVR glove, 4,900 triangles)" "-" -- "$bin" audit "$glove"
    measure "rig audit --moves, FBX (SteamVR glove)" "-" -- "$bin" audit "$glove" --moves "$work/moves.csv" --force
    measure "deform, FBX (SteamVR glove), fist, LBS" "-" -- "$bin" deform "$glove"
fi
measure "deform, 30,000-triangle hand, fist, LBS" "1 s / 200 MB" -- "$bin" deform "$work/hand30k-right.glb"
measure "deform --fix --out, 30,000 triangles, DQS" "1 s / 200 MB" -- "$bin" deform "$work/hand30k-right.glb" --fix --skinning dqs --out "$work/d30k" --force
echo
echo "Growth with X-rays (stats --format json, 10,000 resamples):"
echo
echo "| workload | | wall time | peak memory |"
echo "|---|---|---|---|"
for n in 2500 5000 10k; do
    measure "$n X-rays" "" -- "$bin" stats --data "$work/x$n.csv" --format json
done
echo
echo "Growth with resamples (10,000 X-rays, stats --format json):"
echo
echo "| workload | | wall time | peak memory |"
echo "|---|---|---|---|"
for b in 2500 5000 10000 20000; do
    measure "$b resamples" "" -- "$bin" stats --data "$work/x10k.csv" --format json --resamples "$b"
done
echo
rig_section
kernels_section
