#!/usr/bin/env bash
# Fills the fuzzing corpora from the test fixtures and the shipped data.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/measurements corpus/claims corpus/rig corpus/fbx
cp ../data/measurements.csv corpus/measurements/paper.csv
cp ../data/paper_claims.csv corpus/claims/paper.csv
for f in ../tests/fixtures/bad/*.csv ../tests/fixtures/fuzz/*; do
    [ -e "$f" ] || continue
    case "$(basename "$f")" in
        claims_*) cp "$f" corpus/claims/ ;;
        rig_*) cp "$f" corpus/rig/ ;;
        *) cp "$f" corpus/measurements/ ;;
    esac
done
cp ../docs/examples/*.glb ../docs/examples/*.vrm corpus/rig/
# The real rigs: the WebXR generic hands (siblings, skin weights).
cp ../data/rigs/webxr-generic-hand/left.glb corpus/rig/webxr-left.glb
cp ../data/rigs/webxr-generic-hand/right.glb corpus/rig/webxr-right.glb
# The FBX target: the SteamVR gloves (BSD-3-Clause), when ../shared has them.
for f in ../../shared/rigs/steamvr-gloves/*.fbx; do
    if [ -e "$f" ]; then cp "$f" corpus/fbx/; fi
done
echo "seeded: $(ls corpus/measurements | wc -l) measurement inputs, $(ls corpus/claims | wc -l) claims inputs, $(ls corpus/rig | wc -l) rigs, $(ls corpus/fbx | wc -l) FBX rigs"
