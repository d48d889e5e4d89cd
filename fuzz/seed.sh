#!/usr/bin/env bash
# Fills the fuzzing corpora from the test fixtures and the shipped data.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/measurements corpus/claims corpus/rig corpus/fbx corpus/make
cp ../data/measurements.csv corpus/measurements/paper.csv
cp ../data/paper_claims.csv corpus/claims/paper.csv
for f in ../tests/fixtures/bad/*.csv ../tests/fixtures/fuzz/*; do
    [ -e "$f" ] || continue
    case "$(basename "$f")" in
        claims_*) cp "$f" corpus/claims/ ;;
        rig_*) cp "$f" corpus/rig/ ;;
        make_*) cp "$f" corpus/make/ ;;
        *) cp "$f" corpus/measurements/ ;;
    esac
done
cp ../docs/examples/*.glb ../docs/examples/*.vrm corpus/rig/
# The real rigs: the WebXR generic hands (siblings, skin weights).
cp ../data/rigs/webxr-generic-hand/left.glb corpus/rig/webxr-left.glb
cp ../data/rigs/webxr-generic-hand/right.glb corpus/rig/webxr-right.glb
# Every rig in ../shared/rigs, when there (a worktree reaches it as ../../shared):
# GLB and self-contained .gltf as they are, a .gltf whose buffer is a file beside
# it packed with that file into one GLB (a fuzz input is one file), FBX for the
# FBX target.
shared=""
for d in ../../shared/rigs ../../../shared/rigs; do
    if [ -d "$d" ]; then shared="$d"; break; fi
done
if [ -n "$shared" ]; then
    for f in "$shared"/*/*; do
        dir=$(basename "$(dirname "$f")")
        name="$dir-$(basename "$f")"
        case "$f" in
            *.glb|*.vrm) cp "$f" "corpus/rig/$name" ;;
            *.fbx) cp "$f" "corpus/fbx/$name" ;;
            *.gltf) python3 - "$f" "corpus/rig/${name%.gltf}.glb" <<'PY'
import json, os, struct, sys
src, out = sys.argv[1], sys.argv[2]
doc = json.load(open(src))
uri = doc["buffers"][0].get("uri", "")
if uri.startswith("data:") or not uri:
    open(out[:-4] + ".gltf", "wb").write(open(src, "rb").read())
    sys.exit()
bin = open(os.path.join(os.path.dirname(src), uri), "rb").read()
del doc["buffers"][0]["uri"]
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
bin += b"\0" * (-len(bin) % 4)
body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(bin), 0x004E4942) + bin
open(out, "wb").write(b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body)
PY
            ;;
        esac
    done
fi
# The make target (`phalanx rig` in memory) reads any rig the others read: every
# glTF rig and every FBX rig of theirs.
cp corpus/rig/* corpus/fbx/* corpus/make/ 2> /dev/null || true
echo "seeded: $(ls corpus/measurements | wc -l) measurement inputs, $(ls corpus/claims | wc -l) claims inputs, $(ls corpus/rig | wc -l) rigs, $(ls corpus/fbx | wc -l) FBX rigs, $(ls corpus/make | wc -l) rigs to make"
