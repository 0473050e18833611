#!/usr/bin/env bash
# scene_agree.sh TRAZADOR SCENE: one example scene, 16 samples, same seed, at 96 pixels across:
# the BVH changes nothing (bit-identical files), and the Vulkan back end, validation on, agrees
# with the C reference (PSNR >= 50 dB, at most 0.1% of pixels off by more than 1/255).
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
"$tz" diff "$tmp/cpu.pfm" "$tmp/vk.pfm" --min-psnr 50 --max-diff-share 0.001
