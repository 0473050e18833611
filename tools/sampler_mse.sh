#!/usr/bin/env bash
# sampler_mse.sh: the mean squared error of the linear values against a converged image, random
# sampler against sobol, at equal samples per pixel (issue 23's measure; figures in docs/PERF.md):
#   tools/sampler_mse.sh TRAZADOR SCENE WIDTH [REFERENCE_SPP] [SPP...]
# The reference is sobol under another seed (so it shares no sample with the images measured);
# its own noise adds about MSE(random, 64) / (REFERENCE_SPP / 64) to every figure.
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 TRAZADOR SCENE WIDTH [REFERENCE_SPP] [SPP...]" >&2; exit 2; }
tz=$1 scene=$2 width=$3 ref_spp=${4:-4096}
shift $(($# < 4 ? $# : 4))
spps=("$@")
[ ${#spps[@]} -gt 0 ] || spps=(4 16 64)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
render() { # sampler spp seed out: prints the rendering seconds
    "$tz" render "$scene" --width "$width" --sampler "$1" --spp "$2" --seed "$3" -o "$4" --force 2>&1 |
        sed -n 's/.*, \([0-9.]*\) s rendering.*/\1/p'
}
mse() { "$tz" diff "$1" "$2" | awk '$1 == "rmse" { printf "%.6g", $2 * $2 }' || true; }
render sobol "$ref_spp" 7 "$work/reference.pfm" >/dev/null
printf '%-5s %-12s %-12s %-9s %-10s %-10s\n' spp random sobol ratio random_s sobol_s
for spp in "${spps[@]}"; do
    tr=$(render random "$spp" 1 "$work/random.pfm")
    ts=$(render sobol "$spp" 1 "$work/sobol.pfm")
    mr=$(mse "$work/random.pfm" "$work/reference.pfm")
    ms=$(mse "$work/sobol.pfm" "$work/reference.pfm")
    printf '%-5s %-12s %-12s %-9s %-10s %-10s\n' "$spp" "$mr" "$ms" \
        "$(awk -v a="$mr" -v b="$ms" 'BEGIN { printf "%.2f", a / b }')" "$tr" "$ts"
done
