#!/usr/bin/env bash
# compare_images.sh: renders one fixed set of images with a trazador binary, or compares two such
# sets byte for byte; a refactoring that must not change an image runs it against its base:
#   tests/compare_images.sh render BASE_BINARY base/ && tests/compare_images.sh render NEW new/
#   tests/compare_images.sh compare base/ new/        # exit 0 only when every file is identical
# The set: every example scene, a random scene of 3,000 spheres, a depth-3 sphereflake and path
# scenes, with and without jitter and the BVH, at 4 and 100 spp (the chunk tree), on the CPU back
# end (its fastest build and the one-sample reference build) and on Vulkan where a device exists.
set -euo pipefail
usage() {
    echo "usage: $0 render TRAZADOR OUT_DIR | compare DIR_A DIR_B" >&2
    exit 2
}
[ $# -eq 3 ] || usage
here=$(cd "$(dirname "$0")/.." && pwd)

render_set() {
    local tz=$1 out=$2
    mkdir -p "$out"
    local scenes=("$here"/scenes/*.scene)
    "$tz" gen random --count 3000 --seed 3 -o "$out/random3000.scene" --force >/dev/null
    "$tz" gen sphereflake --depth 3 -o "$out/flake3.scene" --force >/dev/null
    scenes+=("$out/random3000.scene" "$out/flake3.scene")
    local backends=(cpu-fast cpu-ref)
    "$tz" devices >/dev/null 2>&1 && backends+=(vulkan)
    for scene in "${scenes[@]}"; do
        local name
        name=$(basename "$scene" .scene)
        for spp in 4 100; do
            for variant in "" "--no-jitter" "--no-bvh" "--mode path"; do
                for backend in "${backends[@]}"; do
                    local tag="$name-$spp${variant// /}-$backend" build="" flag=cpu
                    [ "$backend" = cpu-ref ] && build=reference
                    [ "$backend" = vulkan ] && flag=vulkan
                    # shellcheck disable=SC2086
                    TRAZADOR_PACKET_BUILD=$build "$tz" render "$scene" --backend "$flag" \
                        --spp "$spp" --width 48 --quiet $variant -o "$out/$tag.pfm" --force \
                        2>"$out/$tag.log" || echo "exit $?" >>"$out/$tag.log"
                done
            done
        done
    done
    rm -f "$out/random3000.scene" "$out/flake3.scene"
}

compare_sets() {
    local a=$1 b=$2 same=0 differ=0
    for f in "$a"/*.pfm "$a"/*.log; do
        local g
        g="$b/$(basename "$f")"
        if [ -f "$g" ] && cmp -s "$f" "$g"; then
            same=$((same + 1))
        else
            differ=$((differ + 1))
            echo "differs: $(basename "$f")"
        fi
    done
    echo "$same identical, $differ different"
    [ "$differ" -eq 0 ]
}

case $1 in
render) render_set "$2" "$3" ;;
compare) compare_sets "$2" "$3" ;;
*) usage ;;
esac
