#!/usr/bin/env bash
# cli_test.sh TRAZADOR SOURCE_DIR: the command line as a user drives it: flags, builds, devices,
# output formats, warnings and the example scenes (cli_files_test.sh: scene errors and the files a
# run writes or leaves alone). The CPU back end, so it runs everywhere.
set -u
tz=$1
src=$2
source "$(dirname "$0")/check.sh"

run help 0 "$tz" --help
has help out "usage: trazador render"
has help out "[--mode report|path]" # issue 24: the synopsis lacked it
grep -qF -- "[--mode report|path]" "$src/README.md" && ok || bad "README's synopsis lacks --mode"
run version 0 "$tz" --version
has version out "trazador 0."
run verbose 0 "$tz" render --backend cpu --width 32 --spp 1 --verbose -o verbose.png
has verbose err "cpu back end: packet integrator build"
# TRAZADOR_PACKET_BUILD picks a build (baseline runs everywhere), and the same image comes out.
TRAZADOR_PACKET_BUILD=baseline run forced-build 0 "$tz" render --backend cpu --width 32 --spp 1 \
    --verbose -o forced.pfm
has forced-build err "packet integrator build baseline, 8 lanes"
"$tz" render --backend cpu --width 32 --spp 1 -o fastest.pfm --quiet
if cmp -s forced.pfm fastest.pfm; then ok; else bad "forced-build: baseline and fastest differ"; fi
# The one-sample reference integrator is a build too (bench times it), with the same image.
TRAZADOR_PACKET_BUILD=reference run reference-build 0 "$tz" render --backend cpu --width 32 \
    --spp 1 --verbose -o reference.pfm
has reference-build err "packet integrator build reference, 8 lanes"
if cmp -s reference.pfm fastest.pfm; then ok; else bad "reference-build: reference and fastest differ"; fi
TRAZADOR_PACKET_BUILD=vax run unknown-build 0 "$tz" render --backend cpu --width 32 --spp 1 \
    -o unknown.png
has unknown-build err "TRAZADOR_PACKET_BUILD=vax: no such build (this binary has "
run no-args 2 "$tz"
run unknown-command 2 "$tz" paint
has unknown-command err "unknown command 'paint'"
run unknown-flag 2 "$tz" render --bogus
has unknown-flag err "unknown option '--bogus'"
has unknown-flag err "usage:"
run bad-spp 2 "$tz" render --spp 0
run bad-backend 2 "$tz" render --backend metal
run bad-extension 2 "$tz" render -o out.txt
has bad-extension err ".png, .ppm, .pfm or .exr"
run width-not-whole 2 "$tz" render --backend cpu --width 7 "$src/scenes/shadows.scene"
has width-not-whole err "--width 7"
has width-not-whole err "pick a width that makes it whole"
# A sphere too small for the ray offset renders, with a warning that names it.
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.1\nsphere lambertian center 0 0 0 radius 1\nsphere mirror center 0 0 0 radius 0.0005\nsphere mirror center 3 0 0 radius 0.0005\n' > tiny.scene
run tiny-sphere 0 "$tz" render --backend cpu --quiet tiny.scene -o tiny.png
has tiny-sphere err "tiny.scene:5:35: radius 0.0005 is under 2 times the ray offset here (0.0003: "
run no-tiny-sphere 0 "$tz" render --backend cpu --spp 1 --width 20 "$src/scenes/shadows.scene" -o s.png
if grep -q "warning" "$tmp/err"; then bad "no-tiny-sphere: warned: $(cat "$tmp/err")"; else ok; fi
# A glass mesh whose bounding box is that thin warns too (a unit cube scaled to half-size 1e-4,
# at the mesh line's file value); at 1e-3, as a sphere of radius 1e-3, it does not.
cp "$src/tests/corpus_mesh/cube.obj" cube.obj
glass_cube() { printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nlight position 0 5 -5 power 10\nmesh refractive file cube.obj scale %s\n' "$1"; }
glass_cube 2e-4 >tiny-glass.scene
run tiny-glass 0 "$tz" render --backend cpu --quiet --spp 1 tiny-glass.scene -o tiny.png
has tiny-glass err "tiny-glass.scene:4:22: mesh 'cube.obj' is glass of half-size 0.0001 (its bounding box's smallest half-extent), under 2 times the ray offset here (0.0001: "
glass_cube 2e-3 >small-glass.scene
run small-glass 0 "$tz" render --backend cpu --quiet --spp 1 small-glass.scene -o tiny.png
[ -s "$tmp/err" ] && bad "small-glass: warned: $(cat "$tmp/err")" || ok
# A quoted path names a file with spaces, quotes and backslashes (issue 49, defect 7: an unknown
# key); it renders as the same file under a plain name, and an unterminated quote is an error at
# its column.
mkdir -p "my models"
cp cube.obj 'my models/my "cube" \.obj'
quoted_cube() { printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nlight position 0 5 -5 power 10\nmesh lambertian file %s scale 0.5\n' "$1"; }
quoted_cube cube.obj >plain-path.scene
quoted_cube '"my models/my \"cube\" \\.obj"' >quoted-path.scene
run plain-path 0 "$tz" render --backend cpu --quiet --spp 1 plain-path.scene -o plain-path.pfm
run quoted-path 0 "$tz" render --backend cpu --quiet --spp 1 quoted-path.scene -o quoted-path.pfm
cmp -s plain-path.pfm quoted-path.pfm && ok || bad "quoted-path: differs from the plain path"
quoted_cube '"my models/cube.obj scale 0.5' >open-quote.scene
run open-quote 2 "$tz" render --backend cpu --quiet --spp 1 open-quote.scene -o open-quote.pfm
has open-quote err "open-quote.scene:4:22: unterminated quoted path"
# The summary's set-up counts the scene's parse, its models' import included (issue 49, defect 9:
# a million-face import showed only under --verbose): at least the parse time --verbose prints,
# whatever the machine's speed (the figures' roundings apart). A grid of 20,000 faces makes the
# import outweigh the rest of the set-up, so that the sum fails where it is left out.
awk 'BEGIN { n = 100; for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) print "v", i / n, j / n, 0
    for (j = 0; j < n; j++) for (i = 0; i < n; i++) { a = j * (n + 1) + i + 1; print "f", a, a + 1, a + n + 2, a + n + 1 } }' >grid.obj
printf 'camera position 0.5 0.5 -2\nplane width 1 height 1 pixel 0.125\nlight position 0 0 -3 power 10\nmesh lambertian file grid.obj\n' >grid.scene
run setup-sum 0 "$tz" render --backend cpu --spp 1 --verbose grid.scene -o grid.png
parse_ms=$(sed -n 's/.*scene: read and parsed in \([0-9.]*\) ms.*/\1/p' "$tmp/err")
setup_s=$(sed -n 's/.* s rendering + \([0-9.]*\) s set-up.*/\1/p' "$tmp/err")
awk -v p="$parse_ms" -v s="$setup_s" 'BEGIN { exit !(p != "" && s != "" && s * 1000 + 0.6 >= p) }' && ok ||
    bad "setup-sum: set-up ${setup_s:-?} s is less than the parse's ${parse_ms:-?} ms"
# Model files where a scene is expected, Blender files and formats (issue 49, defect 8): render
# says that a model is no scene and how to render it, not the parser's byte or directive error;
# a Blender file in a mesh line says which Blender files assimp reads; `trazador formats` lists
# assimp's formats (the README named `assimp listext`, a tool that is not installed).
run formats 0 "$tz" formats
for ext in .obj .ply .stl ".gltf .glb" .dae .blend; do has formats out "  $ext "; done
has formats out "Blender 3D Importer (http://www.blender3d.org) (Blender 2.7x and older only)"
! grep -q "assimp listext" "$src/README.md" "$src/scenes/README.md" && grep -q "trazador formats" "$src/README.md" \
    && ok || bad "formats: the READMEs still name assimp listext"
printf '# a triangle\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >tri.obj
# A model file given as the scene is rendered (issue 51): framed, lit by a white background.
run model-as-scene 0 "$tz" render tri.obj --backend cpu --spp 1 --width 8 -o model.png
grep -q "unknown directive" "$tmp/err" && bad "model-as-scene: the parser's error: $(cat "$tmp/err")" || ok
printf 'glTF\002\000\000\000\020\000\000\000' >"my model.glb"
run glb-as-scene 2 "$tz" render "$tmp/my model.glb" --backend cpu -o model.png
has glb-as-scene err "my model.glb: cannot load: "
printf 'BLENDER-v300REND\000\000\000\000garbage' >new.blend
run blend-as-scene 2 "$tz" render new.blend --backend cpu -o model.png
has blend-as-scene err "new.blend: assimp reads no Blender file newer than 2.7x: export it from Blender as glTF"
run camera-of-scene 2 "$tz" render grid.scene --camera 1 --backend cpu -o model.png
has camera-of-scene err "--camera picks a camera of a model file given as the scene"
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nlight position 0 5 -5 power 10\nmesh file new.blend\n' >blend.scene
run blend-mesh 2 "$tz" render blend.scene --backend cpu -o model.png
has blend-mesh err "blend.scene:4:11: mesh 'new.blend': assimp reads no Blender file newer than 2.7x: export it from Blender as glTF (File > Export > glTF 2.0, a .glb) and load that (assimp: cannot load: "
cp cube.obj cube.xyzq
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nmesh file cube.xyzq\n' >xyzq.scene
run unknown-format 2 "$tz" render xyzq.scene --backend cpu -o model.png
has unknown-format err "this assimp reads no '.xyzq' files (\`trazador formats\` lists those it reads)"
# A scene whose first line is wrong stays a scene with an error, whatever its name says.
printf 'camera position 0 0 -5 bogus 1\n' >bad-first.obj.scene
run bad-scene-first-line 2 "$tz" render bad-first.obj.scene --backend cpu -o model.png
has bad-scene-first-line err "bad-first.obj.scene:1:24: unknown key 'bogus' for camera"
# Where a mesh lies (issue 49, defect 10: the README's recipe framed nothing, without a word):
# --verbose prints each mesh's bounding box after its transform, and a mesh wholly outside the
# camera's view (behind it, off to a side) warns at its file value; one in view, or reaching into
# it from outside, does not.
view_cube() { printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nlight position 0 5 -5 power 10\nmesh lambertian file cube.obj scale 2 translate %s\n' "$1"; }
view_cube "-1 -1 5" >in-view.scene
run in-view 0 "$tz" render in-view.scene --backend cpu --spp 1 --verbose -o view.png
has in-view err "trazador: debug: mesh 'cube.obj' (line 4): 12 faces, bounding box after its transform -1 -1 3 to 1 1 5"
grep -q "warning" "$tmp/err" && bad "in-view: warned: $(grep warning "$tmp/err")" || ok
view_cube "3.5 -1 5" >edge-view.scene # x from 3.5 at z 3: the view's edge is at 2
run edge-view 0 "$tz" render edge-view.scene --backend cpu --spp 1 -q -o view.png
has edge-view err "edge-view.scene:4:22: mesh 'cube.obj' lies wholly outside the camera's view: its bounding box after the transform is 3.5 -1 3 to 5.5 1 5, and the camera at 0 0 -5 looks along 0 0 1"
view_cube "1.5 -1 5" >reaching-view.scene # from 1.5 to 3.5 at z 3 to 5: reaches into the view
run reaching-view 0 "$tz" render reaching-view.scene --backend cpu --spp 1 -q -o view.png
[ -s "$tmp/err" ] && bad "reaching-view: warned: $(cat "$tmp/err")" || ok
{ view_cube "-1 -1 -7"; echo 'mesh lambertian file cube.obj translate 0 9 0'; } >behind-view.scene
run behind-view 0 "$tz" render behind-view.scene --backend cpu --spp 1 -q -o view.png
has behind-view err "behind-view.scene:4:22: mesh 'cube.obj' lies wholly outside the camera's view (and 1 more mesh line): its bounding box after the transform is -1 -1 -9 to 1 1 -7"
[ "$(wc -l <"$tmp/err")" = 1 ] && ok || bad "behind-view: not one warning: $(cat "$tmp/err")"
# A device number past the devices is a command-line error whatever the back end choice.
if "$tz" devices >/dev/null 2>&1; then
    run device-out-of-range 2 "$tz" render --width 20 --spp 1 --device 99 -o dev.png
    has device-out-of-range err "--device 99: there"
    [ ! -e dev.png ] && ok || bad "device-out-of-range wrote dev.png"
    # The largest resolution needs a 4 GiB accumulation buffer: refused with a reason (auto
    # renders it on the CPU), before anything is allocated.
    printf 'camera position 0 0 0\nplane width 16384 height 16384 pixel 1\n' > huge.scene
    run huge-on-vulkan 1 "$tz" render --backend vulkan --spp 1 huge.scene -o huge.pfm
    has huge-on-vulkan err "a 16384 x 16384 region with 1 chunk-tree blocks a pixel needs 4294967296 bytes"
fi
# Whether the default device's driver stops loops silently (lavapipe 22.3; `devices` says what
# the probe found): the Vulkan back end then refuses scenes that could reach the limit.
cuts_loops=$(device_cuts_loops "$tz")
if "$tz" devices 2>/dev/null | grep -q llvmpipe; then
    # With lavapipe the only device, auto renders report mode with the CPU back end, faster there
    # (README), and says why under --verbose.
    "$tz" gen random --count 20000 -o crowd.scene
    run lavapipe-refusal 0 "$tz" render --no-bvh --width 8 --spp 1 --verbose crowd.scene -o crowd.png
    has lavapipe-refusal err "auto: the only Vulkan devices are CPUs; the CPU back end: report mode through the BVH"
    grep -q "error" "$tmp/err" && bad "lavapipe-refusal: an error line: $(cat "$tmp/err")" || ok
    run auto-path-small 0 "$tz" render --width 8 --spp 1 --verbose "$src/scenes/cornell_path.scene" -o cp.png
    # Path mode too, whatever the CPU's packet build (docs/PERF.md, "auto on lavapipe").
    has auto-path-small err "the CPU back end: path mode, where the CPU back end measured faster"
    has auto-path-small err "cpu back end"
    run auto-path-8-lanes 0 env TRAZADOR_PACKET_BUILD=baseline "$tz" render --width 8 --spp 1 \
        --verbose "$src/scenes/cornell_path.scene" -o cp8.png
    has auto-path-8-lanes err "cpu back end"
fi
if $cuts_loops; then
    # Naming the device asks for Vulkan: its refusal is the verdict.
    run lavapipe-refusal-device 1 "$tz" render --no-bvh --width 8 --spp 1 --device 0 crowd.scene \
        -o crowd-device.png
    has lavapipe-refusal-device err "error: this scene needs up to"
fi
# --format names the format of an output without an image extension: /dev/stdout into a pipe.
"$tz" render --backend cpu --width 8 --spp 1 --quiet -o /dev/stdout --format ppm >stdout.ppm
[ "$(head -c 9 stdout.ppm | tr '\n' ' ')" = "P6 8 8 25" ] && ok || bad "--format ppm: $(head -c 9 stdout.ppm)"
# Appended to a file (>>), /dev/stdout is written where the stream stands, not from the start.
echo HEADER >appended.txt
"$tz" render --backend cpu --width 8 --spp 1 --quiet -o /dev/stdout --format ppm >>appended.txt
[ "$(head -c 9 appended.txt | tr '\n' ' ')" = "HEADER P6" ] && ok || bad "--format >>: $(head -c 9 appended.txt)"
# --format alone names the default output after it; an extension of another format is refused.
"$tz" render --backend cpu --width 8 --spp 1 --quiet --format pfm && [ -s render.pfm ] && ok || bad "--format pfm: no render.pfm"
run format-clash 2 "$tz" render --backend cpu --width 8 --spp 1 -o clash.pfm --format png
has format-clash err "output 'clash.pfm' names another format than --format"
"$tz" render --backend cpu --width 8 --spp 1 --quiet -o - --format pfm >dash.pfm
[ "$(head -c 2 dash.pfm)" = "PF" ] && [ ! -e ./- ] && ok || bad "-o - --format pfm: $(head -c 9 dash.pfm)"
run dash-no-format 2 "$tz" render --backend cpu --width 8 --spp 1 -o -
has dash-no-format err "-o - (standard output) needs --format png|ppm|pfm"
run no-format 2 "$tz" render --backend cpu --width 8 --spp 1 -o /dev/stdout
has no-format err "must end in .png, .ppm, .pfm or .exr, or take --format"
run bad-format 2 "$tz" render --backend cpu --width 8 --spp 1 -o x.img --format jpg
has bad-format err "--format takes png, ppm, pfm or exr, got 'jpg'"
# Contradictions and numbers that are not plain decimal integers are usage errors.
run device-with-cpu 2 "$tz" render --backend cpu --device 0 --width 8 --spp 1 -o devcpu.png
has device-with-cpu err "cannot go with --backend cpu"
run validate-with-cpu 2 "$tz" render --backend cpu --validate --width 8 --spp 1 -o valcpu.png
has validate-with-cpu err "--validate turns on Vulkan's validation"
run spp-space 2 "$tz" render --backend cpu --width 8 --spp " 5" -o sppbad.png
[ ! -e devcpu.png ] && [ ! -e sppbad.png ] && ok || bad "a usage error wrote an image"
# Every subcommand takes --help: its usage on stdout, exit 0.
for cmd in render diff gen bench devices formats; do
    run "$cmd-help" 0 "$tz" $cmd --help
    has "$cmd-help" out "usage: trazador $cmd"
done
# bench: a bad flag is a usage error; Vulkan asked for without a device is one error line, at once.
run bench-usage 2 "$tz" bench --spp 0
has bench-usage err "bench --spp takes a whole number from 1 to 65536, got '0'"
run bench-bad-flag 2 "$tz" bench --fast
has bench-bad-flag err "bench: unknown option '--fast'"
has bench-bad-flag err "usage: trazador bench"
VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json run bench-no-device 1 \
    "$tz" bench --backend vulkan
has bench-no-device err "no Vulkan device found"
[ "$(wc -l <"$tmp/err")" = 1 ] && [ ! -s "$tmp/out" ] && ok || bad "bench-no-device: $(cat "$tmp/err")"
# No driver with --validate: the one line, not the loader's own complaint before it.
VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json run validate-no-driver 1 \
    "$tz" render --backend vulkan --validate --width 8 --spp 1 -o nodriver.png
[ "$(wc -l <"$tmp/err")" = 1 ] && ok || bad "validate-no-driver: $(cat "$tmp/err")"
# A broken driver manifest: one line naming the likely cause, not a raw result code.
echo '{bogus' >bogus.json
VK_ICD_FILENAMES=$tmp/bogus.json VK_DRIVER_FILES=$tmp/bogus.json run bogus-manifest 1 \
    "$tz" render --backend vulkan --width 8 --spp 1 -o bogus.png
[ "$(wc -l <"$tmp/err")" = 1 ] && grep -qE "no Vulkan device found|a broken driver manifest" "$tmp/err" \
    && ok || bad "bogus-manifest: $(cat "$tmp/err")"
# Naming a device without any Vulkan device fails like --backend vulkan does, no CPU fallback.
VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json run device-without-vulkan 1 \
    "$tz" render --width 8 --spp 1 --device 0 -o nodev.png
has device-without-vulkan err "no Vulkan device found"
[ ! -e nodev.png ] && ok || bad "device-without-vulkan wrote nodev.png"
# /dev/stdout into a pipe is written in place (it was followed as a link and failed).
"$tz" gen random --count 3 -o /dev/stdout | cat > piped.scene
[ "${PIPESTATUS[0]}" = 0 ] && grep -q "^sphere" piped.scene && ok || bad "gen -o /dev/stdout into a pipe"
# A sample of infinite radiance is dropped and counted; a pixel left with none is named black.
printf 'camera position 0 0 -6\nplane width 0.01 height 0.01 pixel 0.01\nlight position 0 0 -1.1 power 3e38\nsphere lambertian center 0 0 0 radius 1\n' >inf.scene
run nonfinite 0 "$tz" render inf.scene --backend cpu --no-jitter --spp 2 -o inf.pfm
has nonfinite err "2 samples had non-finite radiance and were not accumulated; 1 pixel kept no sample and is black"
# '-' as the scene reads standard input, as -o - writes standard output.
"$tz" gen random --count 3 | "$tz" render - --width 8 --spp 1 --backend cpu -o stdin.pfm 2>/dev/null
"$tz" render piped.scene --width 8 --spp 1 --backend cpu -o file.pfm 2>/dev/null
cmp -s stdin.pfm file.pfm && ok || bad "render - did not render the scene piped in"
printf 'sphere lambertian\n' >missing-center.scene
run stdin-error 2 "$tz" render - -o bad.png <missing-center.scene
has stdin-error err "<stdin>:1:1: sphere is missing required key 'center'"
run dir-output 1 "$tz" gen random --count 3 -o "$tmp/"
has dir-output err "is a directory"
# Output that cannot be written fails the run: diff's metrics to a full disk are data.
"$tz" render --backend cpu --width 8 --spp 1 --quiet -o d.png
"$tz" diff d.png d.png > /dev/full 2> full.err && bad "diff into /dev/full: exit 0" || ok
grep -q "cannot write to standard output" full.err && ok || bad "diff into /dev/full: $(cat full.err)"
# A stream that never ends is refused at once, not read to the size limit.
run endless-stream 2 timeout 20 "$tz" render --backend cpu /dev/zero
has endless-stream err "/dev/zero:1:1: unexpected NUL byte"
# ... and so is an endless stream of bad lines, at its first bad line (issue 24: it was read to
# the 2 GiB limit); a good stream is read whole (the stdin tests above).
yes | run endless-bad-lines 2 timeout 20 "$tz" render --backend cpu -
has endless-bad-lines err "<stdin>:1:1: unknown directive 'y'"
{ printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\n'; yes 'sphere lambertian center 0 0 0 radius 1 bogus 1'; } \
    | run endless-bad-spheres 2 timeout 20 "$tz" render --backend cpu -
has endless-bad-spheres err "<stdin>:3:41: unknown key 'bogus' for sphere lambertian"
# Far from the origin the ray offset is a near clip (10 units at 1e5): a sphere that close warns.
printf 'camera position 1e5 0 0\nplane width 1 height 1 pixel 0.25\nsphere lambertian center 1e5 0 60 radius 55\n' > far.scene
run far-camera 0 "$tz" render --backend cpu --quiet far.scene -o far.png
has far-camera err "far.scene:1:17: camera rays start 10 along their path"
has far-camera err "sphere 1 (centre 100000 0 60, radius 55) has its surface 5 from the camera"
# Faces too, the nearest named by its corners: this quad rendered black without a word. One
# wholly behind the camera does not count.
far_quad() { printf 'camera position 0 0 99999 direction 0 0 1\nplane width 4 height 3 pixel 0.0625\nlight position 0 0 99999 power 10\nquad lambertian v0 -1 -1 %s v1 1 -1 %s v2 1 1 %s v3 -1 1 %s\n' "$1" "$1" "$1" "$1"; }
far_quad 100001 >far-quad.scene
run far-quad 0 "$tz" render --backend cpu --quiet --spp 1 far-quad.scene -o far.png
has far-quad err "far-quad.scene:1:17: camera rays start 9.9999 along their path this far from the origin (the ray offset grows with it), and triangle 1 (corners -1 -1 100001, 1 -1 100001, 1 1 100001) is 2 from the camera: it may be cut away; move the scene nearer the origin"
far_quad 99997 >behind-quad.scene
run behind-quad 0 "$tz" render --backend cpu --quiet --spp 1 behind-quad.scene -o far.png
[ -s "$tmp/err" ] && bad "behind-quad: warned: $(cat "$tmp/err")" || ok
# A camera inside a small emitting cube far from the origin: the near clip cuts all of it away.
printf 'camera position 0 0 100000\nplane width 1 height 1 pixel 0.25\nmesh lambertian file cube.obj scale 0.5 translate -0.25 -0.25 100000.25 color 0 0 0 emission 1 1 1\nrender mode path\n' >inside.scene
run inside-mesh 0 "$tz" render --backend cpu --quiet --spp 1 inside.scene -o far.png
has inside-mesh err "inside.scene:1:17: camera rays start 10 along their path this far from the origin (the ray offset grows with it), and triangle 1 (corners -0.25 -0.25 100000.25, 0.25 0.25 100000.25, -0.25 0.25 100000.25) is 0.25 from the camera"
# Ordinary scenes of faces (the Cornell box's quads, mesh.scene's meshes) do not warn.
for scene in cornell_box mesh; do
    run "quiet-$scene" 0 "$tz" render "$src/scenes/$scene.scene" --backend cpu --spp 1 --width 40 -q -o s.png
    [ -s "$tmp/err" ] && bad "quiet-$scene: warned: $(cat "$tmp/err")" || ok
done
# A sphere too big for single precision to place its surface near the camera warns (a floor of
# radius 3e7 one unit under the camera rendered black); 3e6 is fine. Past 1e18 it is an error.
floor() { printf 'camera position 0 1 -5\nplane width 1 height 1 pixel 0.25\nsphere lambertian center 0 -%s 0 radius %s\nlight position 0 5 -5 power 10\n' "$1" "$1"; }
floor 3e7 >huge-floor.scene
run huge-floor 0 "$tz" render --backend cpu --quiet huge-floor.scene -o floor.png
has huge-floor err "huge-floor.scene:1:17: sphere 1 (centre 0 -3e+07 0, radius 3e+07) is too big for its surface to lie this near the camera: at its size single-precision positions are 2 apart"
# A small sphere touching the camera is the near clip's business, not precision's.
printf 'camera position 0 0 -1\nplane width 1 height 1 pixel 0.25\nsphere lambertian center 0 0 0 radius 1\n' >touch.scene
run touching 0 "$tz" render --backend cpu --quiet touch.scene -o touch.png
has touching err "touch.scene:1:17: camera rays start 0.0001 along their path, and sphere 1 (centre 0 0 0, radius 1) has its surface 0 from the camera"
floor 3e6 >big-floor.scene
run big-floor 0 "$tz" render --backend cpu --quiet big-floor.scene -o floor.png
[ -s "$tmp/err" ] && bad "big-floor: warned: $(cat "$tmp/err")" || ok
# A huge floor quad: near the camera single precision finds its distances less exactly than the
# ray offset, and under a low light its halves may shade each other in dark specks (half-size
# 1e6: 0.2% of the floor); it warns, naming the face. 1e5 does not.
quad_floor() { printf 'camera position 0 1 -4 direction 0 -0.2 1\nplane width 1 height 1 pixel 0.25\nquad lambertian v0 -%s 0 -%s v1 %s 0 -%s v2 %s 0 %s v3 -%s 0 %s\nlight position 0 5 -5 power 10\n' "$1" "$1" "$1" "$1" "$1" "$1" "$1" "$1"; }
quad_floor 1e6 >huge-quad.scene
run huge-quad 0 "$tz" render --backend cpu --quiet huge-quad.scene -o floor.png
has huge-quad err "huge-quad.scene:1:17: triangle 1 (corners -1e+06 0 -1e+06, 1e+06 0 -1e+06, 1e+06 0 1e+06) reaches over 131072 times as far from the origin as the camera"
quad_floor 1e5 >big-quad.scene
run big-quad 0 "$tz" render --backend cpu --quiet big-quad.scene -o floor.png
[ -s "$tmp/err" ] && bad "big-quad: warned: $(cat "$tmp/err")" || ok
floor 2e19 >overflow-floor.scene
run overflow-floor 2 "$tz" render --backend cpu --quiet overflow-floor.scene -o floor.png
has overflow-floor err "overflow-floor.scene:3:28: center must be in [-1e+18, 1e+18], got -2e19"
# Finite samples that sum past the float range are reported, not silently written as inf.
printf 'camera position 0 0 0\nplane width 1 height 1 pixel 0.5\nbackground 3e38 1e38 1\n' > bright.scene
run overflow 0 "$tz" render --backend cpu --quiet bright.scene -o bright.pfm
has overflow err "4 pixels summed their samples past the float range"
# Half-float EXR overflow is reported as PFM's is (issue 24, defect 11); float EXR keeps it.
printf 'camera position 0 0 0\nplane width 1 height 1 pixel 0.5\nbackground 1e5 1 1\n' > half.scene
run half-overflow 0 "$tz" render --backend cpu --quiet half.scene -o half.exr
has half-overflow err "half.exr: 4 pixels past 65504, the largest half float, are infinite in this half EXR (--exr-type float keeps them)"
run float-no-overflow 0 "$tz" render --backend cpu --quiet half.scene --exr-type float -o float.exr
[ -s "$tmp/err" ] && bad "float-no-overflow: warned: $(cat "$tmp/err")" || ok
# A whole height over the limit names the limit, not wholeness.
printf 'camera position 0 0 -5\nplane width 1 height 4 pixel 0.01\n' > tall.scene
run width-too-tall 2 "$tz" render --backend cpu --width 8000 tall.scene
has width-too-tall err "gives a height of 32000 pixels for a 1 x 4 plane; the height must be 1 to 16384"

# --mode path enables emission in a scene without 'render mode path' (issue 24, defect 1), in
# either spelling and on either back end; --mode seed refuses it at the emission's line:col.
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nsphere lambertian center 0 0 0 radius 1 emission 1 1 1\n' >glow.scene
run mode-path-emission 0 "$tz" render glow.scene --backend cpu --spp 1 --mode path -q -o glow.pfm
[ -s glow.pfm ] && ok || bad "mode-path-emission: no image"
run mode-path-equals 0 "$tz" render glow.scene --backend cpu --spp 1 --mode=path -q -o glow2.pfm
if "$tz" devices >/dev/null 2>&1; then
    run mode-path-vulkan 0 "$tz" render glow.scene --backend vulkan --spp 1 --mode path -q -o glow3.pfm
fi
run mode-seed-emission 2 "$tz" render glow.scene --backend cpu --spp 1 -o glow4.pfm
has mode-seed-emission err "glow.scene:3:41: emission needs path mode: add 'render mode path'"
printf 'render mode path\n' >>glow.scene
run mode-seed-flag-emission 2 "$tz" render glow.scene --backend cpu --spp 1 --mode seed -o glow4.pfm
has mode-seed-flag-emission err "glow.scene:3:41: emission needs path mode, and the render was asked for in report mode (--mode report)"
[ ! -e glow4.pfm ] && ok || bad "mode-seed-emission wrote glow4.pfm"
# "seed" is report mode's old name, still taken by --mode and by `render mode` (issue 20).
run mode-report-flag-emission 2 "$tz" render glow.scene --backend cpu --spp 1 --mode report -o glow4.pfm
has mode-report-flag-emission err "the render was asked for in report mode (--mode report)"
"$tz" render --backend cpu --spp 2 --width 40 --mode seed -q -o mode_seed.pfm
"$tz" render --backend cpu --spp 2 --width 40 --mode report -q -o mode_report.pfm
sed 's/^render /render mode seed /' "$src/scenes/cornell.scene" >mode_seed.scene
"$tz" render mode_seed.scene --backend cpu --spp 2 --width 40 -q -o mode_seed_scene.pfm
cmp -s mode_seed.pfm mode_report.pfm && cmp -s mode_seed.pfm mode_seed_scene.pfm && ok ||
    bad "--mode seed, --mode report and 'render mode seed' differ"

# A fov so small that the plane lies past single precision's reach is an error at the fov,
# naming the smallest that works (issue 24, defect 7: it rendered only the background); a
# small one that works renders the sphere, not the background.
fov_scene() { printf 'camera position 0 0 -5 fov %s\nplane width 4 height 4 pixel 4\nlight position 0 0 -5 power 50\nsphere lambertian center 0 0 0 radius 1\n' "$1"; }
fov_scene 1e-17 >tiny-fov.scene
run tiny-fov 2 "$tz" render tiny-fov.scene --backend cpu --spp 1 -o tiny-fov.ppm
has tiny-fov err "tiny-fov.scene:1:28: fov 1e-17 puts the image plane of a plane 4 wide past 1e+19 away, where single precision overflows: give a fov of at least 2.3e-17"
[ ! -e tiny-fov.ppm ] && ok || bad "tiny-fov wrote an image"
fov_scene 1e-15 >small-fov.scene
run small-fov 0 "$tz" render small-fov.scene --backend cpu --spp 1 --no-jitter -q -o small-fov.ppm
[ "$(tail -c 3 small-fov.ppm | od -An -tu1 | tr -d ' ')" != 000 ] && ok || bad "small-fov: the pixel is the background"

# --region and --samples take digits and separators only, as --spp takes digits only (issue 24).
run region-space 2 "$tz" render --backend cpu --spp 1 --width 8 --region '0, 8,0,8' -o sp.exr
has region-space err "--region '0, 8,0,8' must be X0,X1,Y0,Y1"
run samples-space 2 "$tz" render --backend cpu --spp 16 --width 8 --samples ' 0:16' -o sp.exr
has samples-space err "--samples ' 0:16' must be A:B"
run samples-sign 2 "$tz" render --backend cpu --spp 16 --width 8 --samples '+0:16' -o sp.exr
# Singular forms (issue 24): one sample, one pixel, one part.
run nonfinite-one 0 "$tz" render inf.scene --backend cpu --no-jitter --spp 1 -o inf1.pfm
has nonfinite-one err "1 sample had non-finite radiance and was not accumulated; 1 pixel kept no sample and is black"
"$tz" render --backend cpu --spp 1 --width 8 --part -q -o one.exr
run merge-one 0 "$tz" merge one.exr -o one.pfm
has merge-one err "one.pfm: 1 part of 8x8"

# SIGUSR1 without --checkpoint is ignored, and -v says why (issue 24: it killed the render, 138).
# The render is stopped once the line is out, signalled and continued, so the signal lands
# mid-render.
rm -f usr1.pfm
"$tz" render --backend cpu --spp 1024 --width 64 -v -o usr1.pfm 2>usr1.err &
pid=$!
for _ in $(seq 1000); do grep -q "SIGUSR1: ignored" usr1.err 2>/dev/null && break; sleep 0.01; done
kill -STOP $pid; kill -USR1 $pid; kill -CONT $pid
wait $pid
rc=$?
[ $rc = 0 ] && [ -s usr1.pfm ] && ok || bad "SIGUSR1 without --checkpoint: exit $rc: $(tail -n 2 usr1.err)"
grep -q "SIGUSR1: ignored, as it asks for a checkpoint and there is no --checkpoint" usr1.err && ok \
    || bad "SIGUSR1 without --checkpoint: -v did not say it is ignored"

# A scene that nothing lights renders black, with one warning (issue 49, defect 6: exit 0 and no
# word), in either mode; a light of some power, a background that is not black, or an emitter in
# path mode lights it.
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nsphere lambertian center 0 0 0 radius 1\n' >dark.scene
run dark 0 "$tz" render dark.scene --backend cpu --spp 1 -q -o dark.png
has dark err "trazador: warning: dark.scene: nothing lights this scene (no light of some power and colour, no emitting sphere or face, a black background): the image will be black"
[ "$(wc -l <"$tmp/err")" = 1 ] && ok || bad "dark: not one line: $(cat "$tmp/err")"
run dark-path 0 "$tz" render dark.scene --backend cpu --spp 1 -q --mode path -o dark.png
has dark-path err "dark.scene: nothing lights this scene"
{ cat dark.scene; echo 'light position 0 0 -5 power 0'; } >dark-light.scene
run dark-light 0 "$tz" render dark-light.scene --backend cpu --spp 1 -q -o dark.png
has dark-light err "nothing lights this scene"
run dark-stdin 0 "$tz" render - --backend cpu --spp 1 -q -o dark.png <dark.scene
has dark-stdin err "<stdin>: nothing lights this scene"
{ cat dark.scene; echo 'light position 0 0 -5 power 10'; } >lit.scene
{ cat dark.scene; echo 'background 0 0 0.1'; } >sky.scene
{ cat dark.scene; echo 'sphere lambertian center 0 3 0 radius 1 emission 1 1 1'; } >lamp.scene
for lit in lit sky; do
    run "$lit-lit" 0 "$tz" render "$lit.scene" --backend cpu --spp 1 -q -o dark.png
    [ -s "$tmp/err" ] && bad "$lit-lit: warned: $(cat "$tmp/err")" || ok
done
run lamp-lit 0 "$tz" render lamp.scene --backend cpu --spp 1 -q --mode path -o dark.png
[ -s "$tmp/err" ] && bad "lamp-lit: warned: $(cat "$tmp/err")" || ok

# Flags that do nothing for the output or the mode are said once (issue 24, Also).
run exr-type-png 0 "$tz" render --backend cpu --spp 1 --width 8 --exr-type float -o unused.png
has exr-type-png err "--exr-type does nothing for an output that is no EXR"
run tonemap-pfm 0 "$tz" render --backend cpu --spp 1 --width 8 --tonemap linear -o unused.pfm
has tonemap-pfm err "--tonemap does nothing for a pfm output: it sets 8-bit encoding (PNG, PPM), and PFM is linear"
run exr-type-part 0 "$tz" render --backend cpu --spp 1 --width 8 --exr-type half --part -o unused.exr
has exr-type-part err "--exr-type does nothing for a part: it sets an EXR image's channels (parts are always float)"
run merge-tonemap-exr 0 "$tz" merge unused.exr --tonemap srgb -o unused2.exr
has merge-tonemap-exr err "--tonemap does nothing for an exr output"
run tonemap-png 0 "$tz" render --backend cpu --spp 1 --width 8 --tonemap linear -q -o used.png
[ -s "$tmp/err" ] && bad "tonemap-png: warned: $(cat "$tmp/err")" || ok
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nrender roulette off\nlight position 0 5 -5 power 10\n' >roulette.scene
run roulette-seed 0 "$tz" render roulette.scene --backend cpu --spp 1 -q -o roulette.png
has roulette-seed err "roulette.scene:3:8: roulette does nothing in report mode: it is path mode's Russian roulette"
run roulette-path 0 "$tz" render roulette.scene --backend cpu --spp 1 -q --mode path -o roulette.png
[ -s "$tmp/err" ] && bad "roulette-path: warned: $(cat "$tmp/err")" || ok
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nrender light_samples 2\n' >ls.scene
run light-samples-report 0 "$tz" render ls.scene --backend cpu --spp 1 -q -o ls.png
has light-samples-report err "ls.scene:3:8: light_samples does nothing in report mode: it is path mode's emitter samples a vertex"
run light-samples-flag-report 0 "$tz" render --backend cpu --spp 1 --width 8 --light-samples 2 -q -o ls.png
has light-samples-flag-report err "--light-samples does nothing in report mode"
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nrender mode path indirect off\n' >ind.scene
run indirect-path 0 "$tz" render ind.scene --backend cpu --spp 1 -q -o ind.png
has indirect-path err "ind.scene:3:18: indirect does nothing in path mode: paths bounce until \`bounces\`"
run no-indirect-path 0 "$tz" render --backend cpu --spp 1 --width 8 --mode path --no-indirect -q -o ind.png
has no-indirect-path err "--no-indirect does nothing in path mode: paths bounce until --bounces"
run checkpoint-every-alone 0 "$tz" render --backend cpu --spp 1 --width 8 --checkpoint-every 5 -q -o ce.png
has checkpoint-every-alone err "--checkpoint-every does nothing without --checkpoint"

# Every example scene parses and renders.
for scene in "$src"/scenes/*.scene; do
    run "$(basename "$scene")" 0 "$tz" render "$scene" --backend cpu --spp 1 --width 40 -q -o s.png
done

# A camera direction and up of any nonzero finite length give the image of unit vectors.
camera_scene() { # camera_scene DIRECTION UP
    printf 'camera position 0 0 -5 direction %s up %s\nplane width 2 height 2 pixel 0.05\n' "$1" "$2"
    printf 'light position 2 3 -4 power 50\nsphere phong center 0 0 0 radius 1 color 0.5 0.2 0.1\n'
    printf 'render samples 4\n'
}
camera_scene "0 0 1" "0 1 0" >unit-camera.scene
camera_scene "0 0 1e-19" "0 1e-19 0" >tiny-camera.scene
camera_scene "0 0 3e30" "0 -7e-40 0" >odd-camera.scene
for c in unit tiny odd; do
    run "$c-camera" 0 "$tz" render "$c-camera.scene" --backend cpu -o "$c-camera.pfm" --quiet
done
if cmp -s unit-camera.pfm tiny-camera.pfm; then ok; else bad "tiny-camera: differs from unit vectors"; fi
camera_scene "0 0 1" "0 -1 0" >flipped-camera.scene
"$tz" render flipped-camera.scene --backend cpu -o flipped-camera.pfm --quiet
if cmp -s flipped-camera.pfm odd-camera.pfm; then ok; else bad "odd-camera: differs from unit vectors"; fi

# Feature images and the noise threshold from the command line (test_aov.c and test_adaptive.c
# check what they compute): their refusals; the files --aov-files writes; a merge of a region
# split writes the whole render's feature images; a threshold no pixel passes changes nothing,
# and one every pixel passes at the first decision is the render of its 64 samples.
run aov-unknown 2 "$tz" render --backend cpu --aov albedo,shine -o aov.exr
run aov-png 2 "$tz" render --backend cpu --aov albedo -o aov.png
run aov-files-alone 2 "$tz" render --backend cpu --aov-files -o aov.exr
run aov-files-part 2 "$tz" render --backend cpu --aov depth --aov-files --samples 0:16 -o aov.exr
run aov-files 0 "$tz" render --backend cpu --width 16 --spp 4 -q --aov albedo,depth --aov-files -o aov.pfm
if [ -s aov.albedo.pfm ] && [ -s aov.depth.pfm ] && [ ! -e aov.normal.pfm ]; then ok; else bad "aov-files: not the files asked for"; fi
run aov-part-top 0 "$tz" render --backend cpu --width 16 --spp 4 -q --aov albedo,depth --region 0,16,0,8 -o aov-top.exr
run aov-part-bottom 0 "$tz" render --backend cpu --width 16 --spp 4 -q --aov albedo,depth --region 0,16,8,16 -o aov-bottom.exr
run aov-merge 0 "$tz" merge aov-top.exr aov-bottom.exr -q --aov-files -o aov-merged.pfm
for k in albedo depth; do
    cmp -s "aov.$k.pfm" "aov-merged.$k.pfm" && ok || bad "aov-merge: $k differs from the whole render's"
done
run threshold-samples 2 "$tz" render --backend cpu --noise-threshold 0.1 --samples 16:32 -o t.exr
run threshold-none 0 "$tz" render --backend cpu --width 16 --spp 96 -q --noise-threshold 1e-30 -o t-none.pfm
run threshold-off 0 "$tz" render --backend cpu --width 16 --spp 96 -q -o t-off.pfm
cmp -s t-none.pfm t-off.pfm && ok || bad "threshold-none: differs from the render without one"
run threshold-all 0 "$tz" render --backend cpu --width 16 --spp 96 -q --noise-threshold 1e6 -o t-all.pfm
run threshold-64 0 "$tz" render --backend cpu --width 16 --spp 64 -q -o t-64.pfm
cmp -s t-all.pfm t-64.pfm && ok || bad "threshold-all: differs from the render of 64 samples"
printf 'camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\nlight position 0 5 -5 power 10\nrender noise_threshold -1\n' >t-bad.scene
run threshold-scene-bad 2 "$tz" render --backend cpu t-bad.scene -o t.png

check_summary cli_test
