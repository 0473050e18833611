#!/usr/bin/env bash
# task.sh: one task of the job array submit.sh makes: renders part $SLURM_ARRAY_TASK_ID of
# $TRAZADOR_PARTS into $TRAZADOR_PARTS_DIR/part_ID.exr. Requeue-friendly: a finished part is not
# rendered again; an unfinished one resumes from its checkpoint. When Slurm warns of the time
# limit (SIGUSR1, submit.sh's --signal=B:USR1@120), the render checkpoints and stops (SIGTERM)
# and the task requeues itself, to resume on its next run.
set -euo pipefail

id=${SLURM_ARRAY_TASK_ID:?task.sh runs as a task of a Slurm job array}
n=$TRAZADOR_PARTS
part="$TRAZADOR_PARTS_DIR/part_$id.exr"
checkpoint="$TRAZADOR_PARTS_DIR/checkpoint_$id.exr"
if [ -s "$part" ]; then
    echo "task.sh: $part is already rendered"
    exit 0
fi

# Part id of n: a band of rows (every sample), or a range of samples cut at multiples of the
# chunk size, 16 (every pixel).
case $TRAZADOR_SPLIT in
rows)
    width=${TRAZADOR_SIZE%x*} height=${TRAZADOR_SIZE#*x}
    split=(--region "0,$width,$((id * height / n)),$(((id + 1) * height / n))") ;;
samples)
    spp=$TRAZADOR_SPP
    cut() { local s=$(($1 * spp / n / 16 * 16)); [ "$1" = "$n" ] && s=$spp; echo "$s"; }
    split=(--samples "$(cut "$id"):$(cut $((id + 1)))") ;;
esac
resume=()
[ -s "$checkpoint" ] && resume=(--resume "$checkpoint")
eval "render_flags=($TRAZADOR_RENDER_FLAGS)"

"$TRAZADOR_BIN" render "$TRAZADOR_SCENE" "${render_flags[@]}" "${split[@]}" "${resume[@]}" \
    --checkpoint "$checkpoint" -o "$part" &
render=$!
requeue=false
trap 'requeue=true; kill -TERM "$render"' USR1
trap 'kill -TERM "$render"' TERM INT
# wait returns early when a trapped signal arrives: wait again until the render has exited.
status=0
while :; do
    wait "$render" && status=0 || status=$?
    kill -0 "$render" 2>/dev/null || break
done
if $requeue && [ ! -s "$part" ]; then
    echo "task.sh: time limit near: checkpointed to $checkpoint, requeueing"
    scontrol requeue "${SLURM_ARRAY_JOB_ID}_$id"
    exit 0
fi
[ "$status" = 0 ] && rm -f "$checkpoint"
exit "$status"
