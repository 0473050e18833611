#!/usr/bin/env bash
# scene_agree.sh TRAZADOR SCENE: one example scene, 16 samples, same seed, at 96 pixels across:
# the BVH changes nothing (bit-identical files), and the Vulkan back end, validation on, renders
# the very file of the C reference (docs/DESIGN.md section 8).
# Exits 77 when no Vulkan device exists.
set -u
tz=$1
scene=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
common=(render "$scene" --spp 16 --seed 7 --width 96 --quiet)
"$tz" "${common[@]}" --backend cpu -o "$tmp/cpu.pfm" || exit 1
"$tz" "${common[@]}" --backend cpu --no-bvh -o "$tmp/cpu-nobvh.pfm" || exit 1
if ! cmp -s "$tmp/cpu.pfm" "$tmp/cpu-nobvh.pfm"; then
    echo "FAIL: $scene renders differently with and without the BVH" >&2
    "$tz" diff "$tmp/cpu.pfm" "$tmp/cpu-nobvh.pfm"
    exit 1
fi
if ! "$tz" devices >/dev/null 2>&1; then
    echo "no Vulkan device: skipped"
    exit 77
fi
"$tz" "${common[@]}" --backend vulkan --validate -o "$tmp/vk.pfm" || exit 1
if ! cmp -s "$tmp/cpu.pfm" "$tmp/vk.pfm"; then
    echo "FAIL: $scene renders differently on Vulkan and on the CPU" >&2
    "$tz" diff "$tmp/cpu.pfm" "$tmp/vk.pfm"
    exit 1
fi
