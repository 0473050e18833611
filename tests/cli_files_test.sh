#!/usr/bin/env bash
# cli_files_test.sh TRAZADOR SOURCE_DIR: the command line as a user drives it, its files: scene
# errors, outputs written or refused before the render, nothing overwritten or left behind, diff's
# exit codes, checkpoints and the summary line (cli_test.sh: flags, formats and warnings). The CPU
# back end, so it runs everywhere.
set -u
tz=$1
src=$2
source "$(dirname "$0")/check.sh"
cuts_loops=$(device_cuts_loops "$tz")
# Scene errors: file:line:col, exit 2, nothing written, nothing overwritten.
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.1\nsphere lambertian center 0 0 0 radius -1\n' > bad.scene
run bad-scene 2 "$tz" render bad.scene --backend cpu -o new.png
has bad-scene err "bad.scene:3:"
[ ! -e new.png ] && ok || bad "bad-scene: new.png was created"
echo "precious" > keep.png
run bad-scene-keeps 2 "$tz" render bad.scene --backend cpu -o keep.png
[ "$(cat keep.png)" = precious ] && ok || bad "bad-scene-keeps: keep.png was overwritten"
run missing-scene 2 "$tz" render nowhere.scene --backend cpu
has missing-scene err "nowhere.scene: cannot open"

# A render into a folder that does not exist fails with 1 and leaves nothing behind.
run missing-folder 1 "$tz" render --backend cpu --spp 1 --width 20 --verbose -o no/such/dir/out.png
[ ! -e no ] && ok || bad "missing-folder: created something"
# ... and says so before rendering, not after.
has missing-folder err "no/such/dir/out.png: cannot write in no/such/dir: No such file or directory"
grep -q "rendering in" "$tmp/err" && bad "missing-folder: rendered first" || ok

# The default scene, default output name, summary line; --quiet is quiet.
run default 0 "$tz" render --backend cpu --spp 1 --width 40
[ -s render.png ] && ok || bad "default: render.png missing"
has default err "40x40, 1 spp, cpu back end"
run quiet 0 "$tz" render --backend cpu --spp 1 --width 40 --quiet -o q.ppm
[ ! -s err ] && ok || bad "quiet: stderr not empty: $(cat err)"
[ "$(head -c 13 q.ppm | tr '\n' ' ')" = "P6 40 40 255 " ] && ok || bad "quiet: q.ppm header $(head -c 13 q.ppm)"

# Same seed, same image; another seed, another image; tonemaps differ; diff exit codes.
run seed-a 0 "$tz" render --backend cpu --spp 2 --width 40 --seed 5 -q -o a.pfm
run seed-b 0 "$tz" render --backend cpu --spp 2 --width 40 --seed 5 -q -o b.pfm --threads 1
run seed-c 0 "$tz" render --backend cpu --spp 2 --width 40 --seed 6 -q -o c.pfm
cmp -s a.pfm b.pfm && ok || bad "same seed: images differ"
cmp -s a.pfm c.pfm && bad "other seed: images equal" || ok
run diff-same 0 "$tz" diff a.pfm b.pfm --min-psnr 1000 --max-rmse 0
has diff-same out "psnr inf dB"
run diff-other 1 "$tz" diff a.pfm c.pfm --min-psnr 100
has diff-other out "FAIL"
run diff-usage 2 "$tz" diff a.pfm
# Without thresholds any difference exits 1, as cmp does (issue 24, defect 9).
run diff-no-threshold 1 "$tz" diff a.pfm c.pfm
has diff-no-threshold out "FAIL: the images differ"
run diff-no-threshold-same 0 "$tz" diff a.pfm b.pfm
run tonemap-linear 0 "$tz" render --backend cpu --spp 1 --width 40 -q -o lin.ppm --tonemap linear
cmp -s lin.ppm q.ppm && bad "tonemap linear: same bytes as srgb" || ok
run no-jitter 0 "$tz" render --backend cpu --spp 1 --width 40 -q -o nj.ppm --no-jitter --no-indirect
cmp -s nj.ppm q.ppm && bad "no-jitter no-indirect: same bytes as the default" || ok

# A scene the Vulkan back end refuses on lavapipe (path mode: 4096 lights at each of 16 vertices
# are past its loop limit): auto still renders it, with the CPU back end.
{
    printf 'camera position 0 2 -10\nplane width 0.4 height 0.3 pixel 0.1\nrender mode path\n'
    for k in $(seq 1 4096); do printf 'light position %d 3 -2 power 0.01\n' $((k % 7)); done
    for k in $(seq 1 10); do printf 'sphere lambertian center %d 0 %d radius 0.4\n' $((k % 6)) $((k / 6)); done
} > lights.scene
run many-lights-auto 0 "$tz" render lights.scene --spp 1 --verbose -o lights.png
[ -s lights.png ] && ok || bad "many-lights-auto: no image"
if $cuts_loops; then
    run many-lights-vulkan 1 "$tz" render lights.scene --spp 1 --backend vulkan -o lights-vk.png
    has many-lights-vulkan err "loop passes per sample, past lavapipe's safe limit"
elif "$tz" devices >/dev/null 2>&1; then
    run many-lights-vulkan 0 "$tz" render lights.scene --spp 1 --backend vulkan -o lights-vk.png
fi
# The BVH changes no pixel of a scene big enough to walk it (the example scenes are small
# enough to test every sphere).
"$tz" gen random --count 300 --seed 4 -o crowd300.scene
"$tz" render crowd300.scene --backend cpu --width 40 --spp 2 --quiet -o bvh.pfm
"$tz" render crowd300.scene --backend cpu --width 40 --spp 2 --quiet --no-bvh -o nobvh.pfm
cmp -s bvh.pfm nobvh.pfm && ok || bad "BVH and --no-bvh images differ for 300 random spheres"

# No Vulkan driver at all: an explicit Vulkan request fails with the advice; auto falls back.
export VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json
run no-device 1 "$tz" render --backend vulkan --spp 1 --width 20 -o v.png
has no-device err "mesa-vulkan-drivers"
has no-device err "--backend cpu"
[ ! -e v.png ] && ok || bad "no-device: v.png was written"
run no-device-auto 0 "$tz" render --spp 1 --width 20 -o auto.png
has no-device-auto err "CPU back end"
run no-device-list 1 "$tz" devices
unset VK_DRIVER_FILES VK_ICD_FILENAMES

# Outputs that cannot be written are refused before the render (issue 17, defects 3 and 4).
run newdir-slash 1 "$tz" render --backend cpu --spp 1 --width 20 --verbose -o newdir/ --format png
has newdir-slash err "newdir/: names a folder (it ends in '/'), not a file to write"
grep -q "rendering in" "$tmp/err" && bad "newdir-slash: rendered first" || ok
[ ! -e newdir ] && ok || bad "newdir-slash: created newdir"
run gen-newdir-slash 1 "$tz" gen random --count 3 -o newdir/
has gen-newdir-slash err "names a folder"
long=$(printf 'n%.0s' $(seq 1 251)).png # 255 bytes: the longest name ext4 and tmpfs take
run long-name 0 "$tz" render --backend cpu --spp 1 --width 8 -q -o "$long"
[ -s "$long" ] && ok || bad "long-name: no 255-byte image"
run too-long-name 1 "$tz" render --backend cpu --spp 1 --width 20 --verbose -o "n$long"
has too-long-name err "the file name is 256 bytes long, past the 255 this file system allows"
grep -q "rendering in" "$tmp/err" && bad "too-long-name: rendered first" || ok
ls -A | grep -q trazador- && bad "a temporary file was left: $(ls -A)" || ok
# The scene itself as the output is refused, under any name (defect 8).
cp "$src/scenes/shadows.scene" same.scene
ln same.scene same-link.scene
for out in same.scene ./same-link.scene; do
    run "output-is-scene $out" 2 "$tz" render same.scene --backend cpu --width 20 -o "$out" --format png
    has "output-is-scene $out" err "is the scene being rendered (same.scene)"
done
run output-is-stdin 2 "$tz" render - --backend cpu --width 20 -o same.scene --format png <same.scene
has output-is-stdin err "is the scene being rendered (<stdin>)"
cmp -s same.scene "$src/scenes/shadows.scene" && ok || bad "output-is-scene: the scene was changed"
# So are the files the scene's meshes read: the model and the MTL it names.
printf 'mtllib tri.mtl\nv 0 0 5\nv 1 0 5\nv 0 1 5\nusemtl m\nf 1 2 3\n' >tri.obj
printf 'newmtl m\nKd 0.5 0.2 0.1\n' >tri.mtl
cp tri.obj tri.obj.kept && cp tri.mtl tri.mtl.kept
{ sed -n '/^camera/,/^light/p' same.scene; echo 'mesh file tri.obj'; } >mesh.scene
for out in tri.obj tri.mtl; do
    run "output-is-mesh-file $out" 2 "$tz" render mesh.scene --backend cpu --width 20 -o "$out" --format png
    has "output-is-mesh-file $out" err "is a file the scene's meshes read ($out)"
    cmp -s "$out" "$out.kept" && ok || bad "output-is-mesh-file: $out was changed"
done
# A write-protected output is refused as the shell's > refuses it, even for root; --force
# replaces it, keeping its mode (defect 9).
echo precious >ro.png
chmod 0444 ro.png
run write-protected 1 "$tz" render --backend cpu --spp 1 --width 8 -o ro.png
has write-protected err "ro.png: the file is write-protected (mode 444): --force replaces it"
[ "$(cat ro.png)" = precious ] && ok || bad "write-protected: ro.png was replaced"
run write-protected-force 0 "$tz" render --backend cpu --spp 1 --width 8 -q --force -o ro.png
[ "$(head -c 4 ro.png | tail -c 3)" = PNG ] && [ "$(stat -c %a ro.png)" = 444 ] && ok \
    || bad "--force: ro.png $(stat -c %a ro.png) $(head -c 4 ro.png)"
echo precious >ro.scene
chmod 0444 ro.scene
run gen-write-protected 1 "$tz" gen random --count 3 -o ro.scene
[ "$(cat ro.scene)" = precious ] && ok || bad "gen-write-protected: ro.scene was replaced"
# The folder is synced after the rename, so the new name survives a power cut.
if strace -o /dev/null true 2>/dev/null; then
    strace -f -e trace=openat,fsync -o trace.txt "$tz" render --backend cpu --spp 1 --width 8 -q -o synced.png
    dirfd=$(grep -E 'openat\(.*O_DIRECTORY' trace.txt | tail -1 | sed 's/.*= //')
    [ -n "$dirfd" ] && grep -qE "fsync\($dirfd\) += 0" trace.txt && ok || bad "no fsync of the folder: $(grep -E 'fsync|O_DIRECTORY' trace.txt)"
fi
# A checkpoint is checked as the output is, before the render (issue 24, defect 2): not the
# scene, not write-protected without --force, a folder that exists, a name that fits, an EXR name,
# not the output.
ck="--backend cpu --spp 1 --width 8 -o ck-out.png"
cp same.scene scene.exr
run checkpoint-is-scene 2 "$tz" render scene.exr $ck --checkpoint ./scene.exr
has checkpoint-is-scene err "--checkpoint './scene.exr' is the scene being rendered (scene.exr)"
cmp -s scene.exr same.scene && ok || bad "checkpoint-is-scene: the scene was changed"
run checkpoint-not-exr 2 "$tz" render same.scene $ck --checkpoint same.scene
has checkpoint-not-exr err "--checkpoint 'same.scene' must end in .exr: a checkpoint is an EXR part"
cmp -s same.scene "$src/scenes/shadows.scene" && ok || bad "checkpoint-not-exr: the scene was changed"
run checkpoint-png 2 "$tz" render $ck --checkpoint ck.png
has checkpoint-png err "must end in .exr"
echo precious >ro.exr
chmod 0444 ro.exr
run checkpoint-write-protected 1 "$tz" render $ck --checkpoint ro.exr
has checkpoint-write-protected err "ro.exr: the file is write-protected (mode 444): --force replaces it"
[ "$(cat ro.exr)" = precious ] && ok || bad "checkpoint-write-protected: ro.exr was replaced"
run checkpoint-missing-folder 1 "$tz" render $ck --verbose --checkpoint no/such/ck.exr
has checkpoint-missing-folder err "no/such/ck.exr: cannot write in no/such: No such file or directory"
grep -q "rendering in" "$tmp/err" && bad "checkpoint-missing-folder: rendered first" || ok
run checkpoint-too-long 1 "$tz" render $ck --checkpoint "n${long%.png}.exr"
has checkpoint-too-long err "the file name is 256 bytes long"
run checkpoint-is-output 2 "$tz" render --backend cpu --spp 1 --width 8 --part -o ck-out.exr \
    --checkpoint ./ck-out.exr
has checkpoint-is-output err "--checkpoint './ck-out.exr' is the output 'ck-out.exr'"
[ ! -e ck-out.png ] && [ ! -e ck-out.exr ] && ok || bad "a refused checkpoint rendered"
# Conventions (issue 17): --flag=value, -- ends the options, choices in any case.
"$tz" render --backend cpu --spp 1 --width 20 -q -o plain.pfm
run flag-equals 0 "$tz" render --backend=cpu --spp=1 --width=20 -q --output=equals.pfm
cmp -s plain.pfm equals.pfm && ok || bad "--flag=value: another image"
run flag-equals-bad 2 "$tz" render --spp=x
has flag-equals-bad err "render --spp takes a whole number from 1 to 1048576, got 'x'"
run flag-no-value 2 "$tz" render --quiet=yes
has flag-no-value err "--quiet takes no value"
cp "$src/scenes/shadows.scene" ./-dash.scene
run dash-dash 0 "$tz" render --backend cpu --spp 1 --width 20 -q -o dd.png -- -dash.scene
[ -s dd.png ] && ok || bad "--: -dash.scene not rendered"
run any-case 0 "$tz" render --backend CPU --spp 1 --width 20 -q --format PFM --tonemap Linear -o case.pfm
cmp -s plain.pfm case.pfm && ok || bad "choices in capitals: another image"
run gen-any-case 0 "$tz" gen Random --count 3 -o case.scene
# Each --help describes every flag with its default (or says it is required).
for cmd in render diff bench "gen sphereflake" "gen random"; do
    run "$cmd-help-flags" 0 "$tz" $cmd --help
    # One line per flag, its wrapped text joined.
    awk 'substr($0, 1, 31) == sprintf("%31s", "") { line = line " " $0; next }
         { if (line != "") print line; line = ($0 ~ /^  -/) ? $0 : "" }
         END { if (line != "") print line }' "$tmp/out" >flags.txt
    [ -s flags.txt ] && ! grep -vqE 'default|required' flags.txt && ok \
        || bad "$cmd --help: a flag without its default: $(grep -vE 'default|required' flags.txt)"
done
"$tz" render --help >render-help.txt
for flag in -o --output --format --backend --spp --seed --bounces --indirect --no-indirect \
    --no-jitter --width --threads --device --validate --no-bvh --tonemap --force -q --quiet \
    -v --verbose; do
    grep -qE "^  (-., )?$flag( |,)" render-help.txt && ok || bad "render --help lacks $flag"
done
# diff exits as cmp: 2 when it cannot read or compare, 1 past a threshold.
run diff-unreadable 2 "$tz" diff a.pfm missing.pfm --max-rmse 1
run diff-sizes 2 "$tz" diff a.pfm lights.png
# A UTF-8 byte-order mark is named as such.
printf '\xef\xbb\xbfcamera position 0 0 -5\nplane width 1 height 1 pixel 0.1\n' >bom.scene
run bom 2 "$tz" render bom.scene --backend cpu -o bom.png
has bom err "bom.scene:1:1: a UTF-8 byte-order mark (EF BB BF) starts the file"
# The summary's rates are the render's, the set-up apart (issue 15).
run summary 0 "$tz" render --backend cpu --spp 1 --width 20 -o summary.png
grep -qE "20x20, 1 spp, cpu back end, [0-9.]+ s rendering \+ [0-9.]+ s set-up, [0-9.]+ Msamples/s" \
    "$tmp/err" && ok || bad "summary: $(cat "$tmp/err")"
# On a terminal the progress line moves during a Vulkan render, with its rate and time left.
if "$tz" devices 2>/dev/null | grep -q llvmpipe && script -qec true /dev/null >/dev/null 2>&1; then
    script -qec "'$tz' render --backend vulkan --spp 4 -o tty.png" /dev/null >tty.txt
    tr '\r' '\n' <tty.txt | grep -c "rendering  *[0-9.]*%, [0-9.]* s, [0-9.]* Msamples/s, [0-9.]* s left" >steps.txt
    [ "$(cat steps.txt)" -ge 2 ] && grep -q "rendering  50.0%" tty.txt && ok \
        || bad "vulkan progress did not move: $(tr '\r' '\n' <tty.txt | head -c 600)"
fi
# The CPU back end's line has the same parts (a render long enough for two prints).
if script -qec true /dev/null >/dev/null 2>&1; then
    script -qec "'$tz' render --backend cpu --threads 1 --spp 256 -o tty.png" /dev/null >tty.txt
    tr '\r' '\n' <tty.txt | grep -c "rendering  *[0-9.]*%, [0-9.]* s, [0-9.]* Msamples/s, [0-9.]* s left" >steps.txt
    [ "$(cat steps.txt)" -ge 2 ] && ok || bad "cpu progress: $(tr '\r' '\n' <tty.txt | head -c 600)"
fi

check_summary cli_files_test
