#!/usr/bin/env bash
# submit.sh: submits a trazador render to Slurm as a job array of N parts (sbatch --array), each
# task running task.sh (checkpointing, requeued before its time limit, resumed), and a merge job
# that runs once every part has succeeded (--dependency=afterok) and writes the image. Prints the
# two job ids. The merged image is byte-identical to a single render (docs/DESIGN.md, "Parts and
# exact merging").
#
#   tools/slurm/submit.sh [options] SCENE OUT [-- RENDER_FLAGS...]
#     --parts N         parts (default 4)
#     --split rows|samples
#                       rows: N bands of rows, every sample; samples: N ranges of samples,
#                       every pixel, cut at multiples of the chunk size (16) (default rows)
#     --size WxH        the scene's image size (needed by --split rows)
#     --spp N           the render's samples per pixel (needed by --split samples)
#     --dir DIR         folder for the parts, checkpoints and logs, on storage every node sees
#                       (default OUT.parts)
#     --trazador PATH   the trazador binary the nodes run (default: trazador on PATH)
#     --time T          time limit of each part (sbatch --time; default 1:00:00)
#     --sbatch ARG      an extra sbatch argument for both jobs (repeatable: --partition=..., ...)
#     --wait            wait for the merge job (sbatch --wait) and exit with its status
#   RENDER_FLAGS go to every part's `trazador render` (--backend cpu, --spp N, --seed N, ...).
set -euo pipefail

usage() {
    sed -n '2,/^set -euo/{/^#/s/^# \{0,1\}//p}' "$0" >&2
    exit 2
}

wait=() parts=4 split=rows size="" spp="" dir="" trazador=trazador time_limit=1:00:00 extra_sbatch=()
positional=()
while [ $# -gt 0 ]; do
    case $1 in
    --parts) parts=$2; shift 2 ;;
    --split) split=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --dir) dir=$2; shift 2 ;;
    --trazador) trazador=$2; shift 2 ;;
    --time) time_limit=$2; shift 2 ;;
    --sbatch) extra_sbatch+=("$2"); shift 2 ;;
    --wait) wait=(--wait); shift ;;
    --) shift; break ;;
    -h | --help) usage ;;
    -*) echo "submit.sh: unknown option $1" >&2; usage ;;
    *) positional+=("$1"); shift ;;
    esac
done
[ ${#positional[@]} = 2 ] || usage
scene=$(realpath "${positional[0]}")
out=$(realpath -m "${positional[1]}")
dir=$(realpath -m "${dir:-$out.parts}")
[[ $parts =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --parts must be a positive integer" >&2; exit 2; }
case $split in
rows)
    [[ $size =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]] || { echo "submit.sh: --split rows needs --size WxH" >&2; exit 2; }
    [ "${size#*x}" -ge "$parts" ] || { echo "submit.sh: more parts than rows" >&2; exit 2; } ;;
samples)
    [[ $spp =~ ^[1-9][0-9]*$ ]] || { echo "submit.sh: --split samples needs --spp N" >&2; exit 2; } ;;
*) echo "submit.sh: --split is rows or samples" >&2; exit 2 ;;
esac
command -v "$trazador" >/dev/null || [ -x "$trazador" ] || {
    echo "submit.sh: no trazador binary at '$trazador' (--trazador PATH)" >&2
    exit 2
}
trazador=$(command -v "$trazador" || realpath "$trazador")
mkdir -p "$dir/logs"

# What task.sh needs, passed through the job's environment (one shell word per render flag).
render_flags=""
[ $# = 0 ] || render_flags=$(printf '%q ' "$@")
export TRAZADOR_BIN="$trazador" TRAZADOR_SCENE="$scene" TRAZADOR_PARTS_DIR="$dir" \
    TRAZADOR_PARTS="$parts" TRAZADOR_SPLIT="$split" TRAZADOR_SIZE="$size" TRAZADOR_SPP="$spp" \
    TRAZADOR_RENDER_FLAGS="$render_flags"
here=$(dirname "$(realpath "$0")")
array=$(sbatch --parsable --array="0-$((parts - 1))" --job-name=trazador-part \
    --time="$time_limit" --requeue --open-mode=append --signal=B:USR1@120 \
    --output="$dir/logs/part_%a.log" --export=ALL "${extra_sbatch[@]}" "$here/task.sh")
echo "parts: job array $array ($parts tasks)"
merge_command=$(printf '%q merge %q/part_*.exr -o %q' "$trazador" "$dir" "$out")
sbatch --parsable "${wait[@]}" --job-name=trazador-merge --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes --output="$dir/logs/merge.log" "${extra_sbatch[@]}" \
    --wrap "$merge_command" | sed "s|^|merge: job |; s|\$| -> $out|"
