#!/usr/bin/env bash
# parallel_test.sh TRAZADOR SOURCE_DIR: the GNU parallel line of tools/slurm/README.md on the
# local cores: four sample ranges rendered as parts by parallel, merged, byte for byte the single
# render. Exit 77 (skip) only where GNU parallel is not installed (Debian: parallel).
set -euo pipefail
tz=$(realpath "$1")
src=$(realpath "$2")
if ! command -v parallel >/dev/null 2>&1; then
    echo "parallel_test: GNU parallel is not installed (Debian: parallel); skipped"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
cp "$src/scenes/cornell.scene" .
# The README's line, at 48 pixels across so that it takes a second.
parallel --will-cite --link "$tz" render cornell.scene --backend cpu --width 48 --spp 256 --quiet \
    --samples {1}:{2} -o part_{#}.exr ::: 0 64 128 192 ::: 64 128 192 256
"$tz" merge part_*.exr -o merged.pfm --quiet
"$tz" render cornell.scene --backend cpu --width 48 --spp 256 --quiet -o single.pfm
if ! cmp -s merged.pfm single.pfm; then
    echo "parallel_test: FAIL: the merged parts are not the single render" >&2
    exit 1
fi
echo "parallel_test: 4 parts rendered by GNU parallel merge to the single render"
