#!/usr/bin/env bash
# split_test.sh TRAZADOR: split renders end to end on both back ends: a render cut into 4
# regions and into 3 sample ranges, merged, is byte for byte the single render (PFM and float
# EXR); merges of parts that do not fit are refused, naming what is wrong; a render checkpointed
# on SIGUSR1 and stopped by SIGTERM resumes to the uninterrupted image; a time limit says the
# samples each pixel got. No step depends on timing: the checkpoint file is polled for.
set -u
tz=$1
source "$(dirname "$0")/check.sh"
same() { # same NAME A B
    if cmp -s "$2" "$3"; then ok; else bad "$1: $2 and $3 differ"; fi
}

# 40 x 40 pixels, 40 spp: three chunks, the last one short (16 + 16 + 8).
scene="--width 40 --spp 40 --quiet"
for backend in cpu vulkan; do
    r="render $scene --backend $backend"
    run "$backend whole" 0 $tz $r -o whole.pfm
    run "$backend whole exr" 0 $tz $r -o whole.exr --exr-type float
    for k in 0 1 2 3; do
        x0=$(((k % 2) * 17)) x1=$(((k % 2) * 23 + 17)) y0=$((k / 2 * 11)) y1=$((k / 2 * 29 + 11))
        run "$backend region $k" 0 $tz $r --region "$x0,$x1,$y0,$y1" -o "region_$k.exr"
    done
    run "$backend merge regions" 0 $tz merge region_3.exr region_1.exr region_0.exr region_2.exr \
        -o merged.pfm
    same "$backend regions" merged.pfm whole.pfm
    run "$backend merge regions exr" 0 $tz merge region_*.exr -o merged.exr --exr-type float
    same "$backend regions exr" merged.exr whole.exr
    ranges=(0:16 16:32 32:40)
    for k in 0 1 2; do
        run "$backend samples ${ranges[k]}" 0 $tz $r --samples "${ranges[k]}" -o "samples_$k.exr"
    done
    run "$backend merge samples" 0 $tz merge samples_2.exr samples_0.exr samples_1.exr -o merged.pfm
    same "$backend samples" merged.pfm whole.pfm
    # A merged part merges again: two sample ranges of a region, merged with the other parts.
    run "$backend merge as part" 0 $tz merge samples_*.exr --part -o merged_part.exr
    run "$backend merge of a merge" 0 $tz merge merged_part.exr -o merged.pfm
    same "$backend merge of a merge" merged.pfm whole.pfm
    # Staged merges (issue 24, defect 10): a --part merge of some parts is a bigger part, of
    # the smallest box holding them, which merges on; a box they do not fill is refused.
    run "$backend stage samples" 0 $tz merge samples_2.exr samples_1.exr --part -o s12.exr
    run "$backend stage samples on" 0 $tz merge s12.exr samples_0.exr -o merged.pfm
    same "$backend staged samples" merged.pfm whole.pfm
    run "$backend stage regions" 0 $tz merge region_0.exr region_1.exr --part -o top.exr
    run "$backend stage regions on" 0 $tz merge top.exr region_3.exr region_2.exr -o merged.pfm
    same "$backend staged regions" merged.pfm whole.pfm
    run "$backend stage with a gap" 1 $tz merge region_0.exr region_3.exr --part -o gap.exr
    has "$backend stage with a gap" "$tmp/err" "region 17,40,0,11 samples 0:40"
    [ ! -e gap.exr ] && ok || bad "$backend: a refused staged merge wrote its output"
    mkdir -p "$backend"
    cp whole.pfm region_*.exr samples_*.exr "$backend/"
done
# Deeper stacks: 1,000 spp (63 chunks, the last of 8 samples) cut at chunks that are no powers
# of two, the parts given out of order.
for backend in cpu vulkan; do
    deep="render --width 16 --spp 1000 --quiet --backend $backend"
    $tz $deep -o deep_whole.pfm
    $tz $deep --samples 400:1000 -o deep_2.exr
    $tz $deep --samples 0:48 -o deep_0.exr
    $tz $deep --samples 48:400 -o deep_1.exr
    run "$backend deep merge" 0 $tz merge deep_2.exr deep_0.exr deep_1.exr -o deep.pfm
    same "$backend deep samples" deep.pfm deep_whole.pfm
done
# Depth of field: the lens's numbers come from each sample's own sampler dimensions, so a thin
# lens render (scenes/lens.scene, path mode, Sobol) split by regions and samples merges exactly.
lens_scene="$(dirname "$0")/../scenes/lens.scene"
for backend in cpu vulkan; do
    lens="render $lens_scene --width 40 --spp 40 --quiet --backend $backend"
    $tz $lens -o lens_whole.pfm 2>/dev/null
    $tz $lens --region 0,40,0,9 -o lens_top.exr 2>/dev/null
    $tz $lens --region 0,40,9,25 --samples 0:16 -o lens_low0.exr 2>/dev/null
    $tz $lens --region 0,40,9,25 --samples 16:40 -o lens_low1.exr 2>/dev/null
    run "$backend lens merge" 0 $tz merge lens_low1.exr lens_top.exr lens_low0.exr -o lens.pfm
    same "$backend lens split" lens.pfm lens_whole.pfm
done
# The Vulkan back end renders only the region's tiles and the range's samples: its parts merge
# to its own single render (checked above); the two back ends agree to rounding only.

# Refusals.
cd cpu || exit 1
run "overlap" 1 $tz merge region_0.exr region_0.exr region_1.exr region_2.exr region_3.exr -o x.pfm
has "overlap" "$tmp/err" "region_0.exr and region_0.exr both hold samples 0:40 of region 0,17,0,11"
run "gap" 1 $tz merge region_0.exr region_1.exr region_3.exr -o x.pfm
has "gap" "$tmp/err" "missing (region x0,x1,y0,y1 and samples A:B)"
has "gap" "$tmp/err" "region 0,17,11,40 samples 0:40"
run "gap in samples" 1 $tz merge samples_0.exr samples_2.exr -o x.pfm
has "gap in samples" "$tmp/err" "samples 16:32"
$tz render $scene --backend cpu --seed 7 --region 0,17,0,11 -o seed7.exr
run "other seed" 1 $tz merge seed7.exr region_1.exr region_2.exr region_3.exr -o x.pfm
has "other seed" "$tmp/err" "seed7.exr and region_1.exr are parts of different renders"
has "other seed" "$tmp/err" "different renders: seed 7 against 1" # not the digest, which covers it
$tz render --width 40 --spp 48 --quiet --backend cpu --region 0,17,0,11 -o spp48.exr
run "other spp" 1 $tz merge region_1.exr spp48.exr region_2.exr region_3.exr -o x.pfm
has "other spp" "$tmp/err" "are parts of different renders: 40 against 48 samples per pixel"
$tz render --width 20 --spp 40 --quiet --backend cpu --region 0,17,0,11 -o width20.exr
run "other width" 1 $tz merge region_1.exr width20.exr region_2.exr region_3.exr -o x.pfm
has "other width" "$tmp/err" "are parts of different renders: image 40x40 against 20x20"
$tz render $scene --backend cpu --bounces 2 --region 0,17,0,11 -o bounces.exr
run "other settings" 1 $tz merge region_1.exr bounces.exr region_2.exr region_3.exr -o x.pfm
has "other settings" "$tmp/err" "are parts of different renders: scene digest"
run "not a part" 1 $tz merge whole.pfm region_1.exr -o x.pfm
[ ! -e x.pfm ] && ok || bad "a refused merge wrote its output"
run "samples not whole chunks" 2 $tz render $scene --samples 0:20 -o x.exr
has "samples not whole chunks" "$tmp/err" "A a multiple of 16 and B one too or 40"
run "samples past spp" 2 $tz render $scene --samples 32:48 -o x.exr
run "region outside" 2 $tz render $scene --region 0,41,0,40 -o x.exr
has "region outside" "$tmp/err" "0 <= X0 < X1 <= 40"
run "region as png" 2 $tz render $scene --region 0,20,0,40 -o x.png
has "region as png" "$tmp/err" "write an EXR part"
run "merge nothing" 2 $tz merge -o x.pfm
# -o - is standard output, with --format, as for render (issue 24, defect 4).
$tz merge region_*.exr -o - --format pfm >stdout.pfm 2>/dev/null
same "merge -o -" stdout.pfm whole.pfm
[ ! -e ./- ] && ok || bad "merge -o - wrote a file named -"
run "merge -o - without --format" 2 $tz merge region_*.exr -o -
has "merge -o - without --format" "$tmp/err" "-o - (standard output) needs --format"
# The output may not be one of the parts, under its name or a hard link (issue 24, defect 3).
cp region_0.exr region_0.keep
cp region_1.exr region_1.keep
ln region_1.exr region_1.link
run "merge over a part" 2 $tz merge region_0.exr region_1.exr region_2.exr region_3.exr -o region_0.exr
has "merge over a part" "$tmp/err" "output 'region_0.exr' is the part 'region_0.exr' being merged"
run "merge over a link" 2 $tz merge region_*.exr -o region_1.link --format exr
has "merge over a link" "$tmp/err" "is the part 'region_1.exr' being merged"
same "merge over a part leaves it" region_0.exr region_0.keep
same "merge over a link leaves it" region_1.exr region_1.keep
cd .. || exit 1

# Checkpoints. The render is stopped (SIGSTOP) once its handlers are in place (its -v line
# says so), sent the signal and continued, so that the signal comes mid-render whatever the
# speed: SIGUSR1 writes a checkpoint and the render goes on to the uninterrupted image; SIGTERM
# writes one and stops (143); the resumed render is the uninterrupted one.
long="--width 64 --spp 4096"
# signal_render BACKEND SIGNAL OUT: starts the render, signals it mid-render; its exit code.
signal_render() {
    rm -f ck.exr ck.err
    $tz render $long --backend "$1" --checkpoint ck.exr --keep-checkpoint --checkpoint-every 1000 \
        -v -o "$3" 2>ck.err &
    local pid=$!
    for _ in $(seq 1000); do grep -q "checkpoints: to ck.exr" ck.err 2>/dev/null && break; sleep 0.01; done
    kill -STOP $pid
    kill "-$2" $pid
    kill -CONT $pid
    wait $pid
}
for backend in cpu vulkan; do
    $tz render $long --quiet --backend $backend -o long_whole.pfm
    signal_render $backend USR1 long.pfm
    rc=$?
    [ $rc = 0 ] && ok || bad "$backend: exit $rc after SIGUSR1, want 0: $(tail -n 3 ck.err)"
    [ -s ck.exr ] && ok || bad "$backend: no checkpoint after SIGUSR1"
    same "$backend after SIGUSR1" long.pfm long_whole.pfm
    signal_render $backend TERM long.pfm
    rc=$?
    [ $rc = 143 ] && ok || bad "$backend: exit $rc after SIGTERM, want 143: $(tail -n 3 ck.err)"
    grep -q "stopped by SIGTERM at sample" ck.err && ok || bad "$backend: SIGTERM: $(tail -n 3 ck.err)"
    run "$backend resume" 0 $tz render $long --backend $backend --resume ck.exr -o long.pfm
    has "$backend resume" "$tmp/err" "ck.exr: resuming at sample"
    same "$backend resume" long.pfm long_whole.pfm
    if [ $backend = vulkan ]; then # through staging copies, as on a discrete GPU
        TRAZADOR_VK_STAGING=1 run "staged resume" 0 $tz render $long --backend vulkan \
            --resume ck.exr -o staged.pfm
        same "staged resume" staged.pfm long_whole.pfm
        # A stop abandons the pass in flight: its checkpoint is the part as the pass began,
        # read from the snapshot the staging path copies it to.
        TRAZADOR_VK_STAGING=1 signal_render vulkan TERM staged.pfm
        rc=$?
        [ $rc = 143 ] && ok || bad "staged: exit $rc after SIGTERM, want 143: $(tail -n 3 ck.err)"
        TRAZADOR_VK_STAGING=1 run "staged stop, resumed" 0 $tz render $long --backend vulkan \
            --resume ck.exr -o staged.pfm
        same "staged stop, resumed" staged.pfm long_whole.pfm
        TRAZADOR_VK_STAGING=1 run "staged region" 0 $tz render $scene --backend vulkan \
            --region 17,40,11,40 -o staged.exr
        same "staged region" staged.exr vulkan/region_3.exr
    fi
    # A checkpoint of other settings is refused.
    run "$backend resume other" 1 $tz render --width 64 --spp 1024 --backend $backend \
        --resume ck.exr -o other.pfm
    has "$backend resume other" "$tmp/err" "cannot resume this render from it: it holds other samples per pixel: 4096, this render 1024"
    run "$backend resume other seed" 1 $tz render $long --seed 9 --backend $backend \
        --resume ck.exr -o other.pfm
    has "$backend resume other seed" "$tmp/err" "it holds another seed: 1, this render 9"
    run "$backend resume other bounces" 1 $tz render $long --bounces 2 --backend $backend \
        --resume ck.exr -o other.pfm
    has "$backend resume other bounces" "$tmp/err" "it holds another scene or other settings: digest"
done

# Parts and checkpoints of the two back ends differ by rounding: a merge or a resume that mixes
# them is refused naming both; auto resumes on the checkpoint's own back end (issue 24, defect 5).
run "merge of two back ends" 1 $tz merge cpu/region_0.exr vulkan/region_1.exr cpu/region_2.exr \
    cpu/region_3.exr -o mixed.pfm
has "merge of two back ends" "$tmp/err" "cpu/region_0.exr and vulkan/region_1.exr are parts of different renders: back end cpu against vulkan: "
[ ! -e mixed.pfm ] && ok || bad "merge of two back ends wrote its output"
run "resume on the other back end" 1 $tz render $long --backend cpu --resume ck.exr -o other.pfm
has "resume on the other back end" "$tmp/err" "ck.exr: cannot resume this render from it: it was rendered by the vulkan: "
has "resume on the other back end" "$tmp/err" "and --backend cpu asks for the other: the two differ by rounding"
run "resume on auto" 0 $tz render $long --resume ck.exr -o auto.pfm
same "resume on auto" auto.pfm long_whole.pfm
$tz render $long --backend cpu --samples 0:16 -o cpu_ck.exr
run "resume cpu on vulkan" 1 $tz render $long --backend vulkan --resume cpu_ck.exr -o other.pfm
has "resume cpu on vulkan" "$tmp/err" "it was rendered by the cpu back end, and --backend vulkan asks for the other"
run "resume cpu on a device" 1 $tz render $long --device 0 --resume cpu_ck.exr -o other.pfm
has "resume cpu on a device" "$tmp/err" "it was rendered by the cpu back end, and --backend vulkan asks for the other"
[ ! -e other.pfm ] && ok || bad "a refused resume wrote its output"

# A finished render removes its checkpoint once the output is written, unless asked to keep it;
# one cut short by a time limit keeps it (issue 24, Also).
$tz render $scene --backend cpu --samples 0:16 -o removed.exr
cp removed.exr kept.exr
run "checkpoint removed" 0 $tz render $scene --backend cpu --resume removed.exr \
    --checkpoint removed.exr -o removed.pfm
[ ! -e removed.exr ] && [ -s removed.pfm ] && ok || bad "a finished render left its checkpoint"
same "checkpoint removed, the image whole" removed.pfm cpu/whole.pfm
run "checkpoint kept" 0 $tz render $scene --backend cpu --resume kept.exr --checkpoint kept.exr \
    --keep-checkpoint -o kept.pfm
[ -s kept.exr ] && ok || bad "--keep-checkpoint: the checkpoint was removed"
# A kept checkpoint holds the finished part even when the render ended before its first
# periodic checkpoint: merged alone, it is the whole image.
rm -f short_ck.exr
run "checkpoint kept, none periodic" 0 $tz render $scene --backend cpu --checkpoint short_ck.exr \
    --keep-checkpoint -o short.pfm
run "checkpoint kept, merged" 0 $tz merge short_ck.exr -o short_merged.pfm
same "checkpoint kept, the whole image" short_merged.pfm cpu/whole.pfm
tl_ck="render --width 32 --spp 1048576 --backend cpu --quiet"
$tz $tl_ck --samples 0:16 -o tl_ck.exr
run "checkpoint of a time limit" 0 $tz $tl_ck --time-limit 0.3 --resume tl_ck.exr \
    --checkpoint tl_ck.exr -o tl_ck.pfm
[ -s tl_ck.exr ] && ok || bad "a render cut short by its time limit removed its checkpoint"

# A checkpoint that cannot be written (a file size limit standing for a full disk: SIGXFSZ
# ignored, so writes fail with EFBIG) fails the run and leaves the previous checkpoint intact.
# lavapipe of Mesa 25 keeps device memory in a memfd, which the limit caps too: the Vulkan back
# end refuses to start (vk_memory_file_fits) rather than let the driver die of SIGBUS.
cp ck.exr ck_before.exr
(trap '' XFSZ; ulimit -f 16; exec $tz render $long --backend vulkan --resume ck.exr \
    --checkpoint ck.exr --checkpoint-every 0.001 -o full.pfm) 2>full.err
rc=$?
[ $rc = 1 ] && ok || bad "full disk: exit $rc, want 1: $(tail -n 2 full.err)"
same "full disk leaves the checkpoint" ck.exr ck_before.exr
ls .trazador-* >/dev/null 2>&1 && bad "full disk: a temporary file was left" || ok

# A time limit: whole chunks, a line saying how many samples every pixel got; written as a part,
# it is the very part of that many samples.
tl="--width 32 --spp 1048576 --backend cpu"
run "time limit" 0 $tz render $tl --time-limit 0.5 -o tl.pfm
has "time limit" "$tmp/err" "time limit: every pixel got samples 0:"
run "time limit part" 0 $tz render $tl --time-limit 0.3 --part -o tl.exr
n=$(sed -n 's/.*every pixel got samples 0:\([0-9]*\) .*/\1/p' "$tmp/err")
[ -n "$n" ] && [ $((n % 16)) = 0 ] && [ "$n" -gt 0 ] && ok || bad "time limit: '$n' samples, not whole chunks"
run "time limit samples" 0 $tz render $tl --samples "0:$n" -o tl_n.exr
same "time limit as samples 0:$n" tl.exr tl_n.exr

# An environment-lit scene (its map's importance tables, its slot in the emitter pick): regions
# and sample ranges merge to the whole render on both back ends.
sky="$(dirname "$0")/../scenes/sky.scene --width 32 --spp 32 --quiet"
for backend in cpu vulkan; do
    r="render $sky --backend $backend"
    run "$backend sky whole" 0 $tz $r -o sky.pfm
    run "$backend sky top" 0 $tz $r --region 0,32,0,9 -o sky_top.exr
    run "$backend sky bottom 0:16" 0 $tz $r --region 0,32,9,24 --samples 0:16 -o sky_b0.exr
    run "$backend sky bottom 16:32" 0 $tz $r --region 0,32,9,24 --samples 16:32 -o sky_b1.exr
    run "$backend sky merge" 0 $tz merge sky_b1.exr sky_top.exr sky_b0.exr -o sky_merged.pfm
    same "$backend sky split" sky_merged.pfm sky.pfm
done

check_summary split_test
