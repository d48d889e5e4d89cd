#!/usr/bin/env bash
# Fills the fuzzing corpora from the test fixtures and the shipped data.
set -euo pipefail
cd "$(dirname "$0")"
mkdir -p corpus/measurements corpus/claims corpus/rig
cp ../data/measurements.csv corpus/measurements/paper.csv
cp ../data/paper_claims.csv corpus/claims/paper.csv
for f in ../tests/fixtures/bad/*.csv ../tests/fixtures/fuzz/*; do
    [ -e "$f" ] || continue
    case "$(basename "$f")" in
        claims_*) cp "$f" corpus/claims/ ;;
        *) cp "$f" corpus/measurements/ ;;
    esac
done
cp ../docs/examples/*.glb ../docs/examples/*.vrm corpus/rig/
echo "seeded: $(ls corpus/measurements | wc -l) measurement inputs, $(ls corpus/claims | wc -l) claims inputs, $(ls corpus/rig | wc -l) rigs"
