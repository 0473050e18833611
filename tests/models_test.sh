#!/usr/bin/env bash
# models_test.sh TRAZADOR: real models of Debian's assimp-testmodels through the mesh directive.
# Eleven files in ten formats (OBJ with its MTL, FBX, ASCII STL, binary and ASCII PLY, glTF
# binary, COLLADA, 3DS, Blender, DirectX, OFF) load with the face count assimp 5.2 gives them (the
# spider holds the same 1312 faces in OBJ, FBX and STL), are seen from a camera framed for each,
# and render the very same file on the CPU back end and on Vulkan with validation on; files
# without materials (PLY, STL, OFF) render lambertian 0.8 grey; as glass, closed files render and
# open ones are refused naming their first open part; an asymmetric OBJ renders as its faces
# converted by hand into trazador's left-handed space, not as its mirror image. Malformed and
# empty files are refused with file:line:col, exit 2, and leave an existing output untouched.
# Exit 77 (skip) where assimp-testmodels is not installed; Vulkan agreement is skipped, with a
# notice, where no Vulkan device exists (CI installs both).
set -euo pipefail
tz=$(realpath "${1:?models_test.sh TRAZADOR}")
here=$(cd "$(dirname "$0")" && pwd)
models=/usr/share/assimp/models
if [ ! -d "$models" ]; then
    echo "assimp-testmodels is not installed ($models): skipped"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
vulkan=1
"$tz" devices >/dev/null 2>&1 || vulkan=0
[ $vulkan = 1 ] || echo "no Vulkan device: CPU back end only"
failures=0
fail() {
    echo "FAIL: $*" >&2
    failures=$((failures + 1))
}

# scene_for MODEL DISTANCE: a scene looking down +z at the model from DISTANCE, lit from above.
scene_for() {
    printf 'camera position 0 0 -%s direction 0 0 1 up 0 1 0 fov 60\n' "$2"
    printf 'plane width 64 height 48 pixel 1\n'
    printf 'light position 0 %s -%s power %s\n' "$2" "$2" "$(($2 * $2 * 10))"
    printf 'mesh file %s\n' "$models/$1"
}

# black.pfm: the image of nothing seen (the background is black), to diff renders against.
{
    printf 'PF\n64 48\n-1.0\n'
    head -c $((64 * 48 * 12)) /dev/zero
} >"$tmp/black.pfm"

# seen_and_agrees FILE: $tmp/cpu.pfm, the CPU back end's render of $tmp/model.scene, is not
# black, and the Vulkan back end renders the very same file (where a device exists).
seen_and_agrees() {
    local file=$1 rc=0
    "$tz" diff "$tmp/cpu.pfm" "$tmp/black.pfm" >/dev/null 2>&1 || rc=$?
    [ $rc = 1 ] || fail "$file: not seen (every pixel black, or diff failed: exit $rc)"
    [ $vulkan = 1 ] || return 0
    if ! "$tz" render "$tmp/model.scene" --backend vulkan --validate --spp 1 --quiet \
        -o "$tmp/vk.pfm" 2>"$tmp/vk.log"; then
        fail "$file: not rendered on Vulkan: $(tail -1 "$tmp/vk.log")"
    elif ! cmp -s "$tmp/cpu.pfm" "$tmp/vk.pfm"; then
        fail "$file: Vulkan and the CPU back end differ"
        "$tz" diff "$tmp/cpu.pfm" "$tmp/vk.pfm" || true
    fi
}

# model FILE DISTANCE FACES: loads, counts, is seen, and agrees across back ends.
model() {
    local file=$1 distance=$2 faces=$3 out
    scene_for "$file" "$distance" >"$tmp/model.scene"
    if ! out=$("$tz" render "$tmp/model.scene" --backend cpu --spp 1 --verbose \
        -o "$tmp/cpu.pfm" 2>&1); then
        fail "$file: not rendered: $(echo "$out" | tail -1)"
        return
    fi
    grep -q "scene: 0 spheres, $faces triangles" <<<"$out" ||
        fail "$file: expected $faces triangles: $(grep 'scene: 0 spheres' <<<"$out")"
    seen_and_agrees "$file"
}

model OBJ/spider.obj 100 1312
model FBX/spider.fbx 100 1312
model STL/Spider_ascii.stl 3 1312
model PLY/cube_binary.ply 3 12
model PLY/Wuson.ply 3 3732
model glTF2/BoxTextured-glTF-Binary/BoxTextured.glb 3 12
model Collada/duck.dae 3 4212
model 3DS/fels.3ds 3 768
model BLEND/BlenderDefault_276.blend 3 12
model X/test.x 3 12
model OFF/Cube.off 3 12

# no_material FILE DISTANCE: a file without materials renders as the same file given lambertian
# 0.8 grey (scenes/README.md), not as assimp's made-up material (for PLY and STL white with
# specular 1, which became Phong ks 1 over white: more light out than in).
no_material() {
    local file=$1 distance=$2
    scene_for "$file" "$distance" >"$tmp/own.scene"
    scene_for "$file" "$distance" | sed 's/^mesh file /mesh lambertian color 0.8 0.8 0.8 file /' \
        >"$tmp/grey.scene"
    if ! "$tz" render "$tmp/own.scene" --backend cpu --spp 1 --quiet -o "$tmp/own.pfm" 2>/dev/null ||
        ! "$tz" render "$tmp/grey.scene" --backend cpu --spp 1 --quiet -o "$tmp/grey.pfm" \
            2>/dev/null; then
        fail "$file: not rendered without a material"
    elif ! cmp -s "$tmp/own.pfm" "$tmp/grey.pfm"; then
        fail "$file: its made-up material is not lambertian 0.8 grey"
        "$tz" diff "$tmp/own.pfm" "$tmp/grey.pfm" || true
    fi
}

no_material PLY/Wuson.ply 3
no_material PLY/cube_binary.ply 3
no_material STL/Spider_ascii.stl 3
no_material OFF/Cube.off 3

# glass FILE [MESSAGE]: the file as glass (`mesh refractive`) renders, or with MESSAGE is refused
# (exit 2) naming its first open part: glass is checked part by part (parts joined by edges).
glass() {
    local file=$1 want=${2:-} out rc=0
    scene_for "$file" 3 | sed 's/^mesh file /mesh refractive file /' >"$tmp/glass.scene"
    out=$("$tz" render "$tmp/glass.scene" --backend cpu --spp 1 -o "$tmp/glass.pfm" 2>&1) || rc=$?
    if [ -z "$want" ]; then
        [ $rc = 0 ] || fail "$file as glass: exit $rc: $out"
    else
        [ $rc = 2 ] || fail "$file as glass: exit $rc, expected 2"
        grep -qF "$want" <<<"$out" || fail "$file as glass: '$want' not in: $out"
    fi
}

glass PLY/cube_binary.ply
glass OFF/Cube.off
glass STL/sphereWithHole.stl "a refractive part is not closed: 285 faces of material \
'DefaultMaterial' from face 1, between 0 0 0 and 3 3 3; its edge"
# Wuson's first 1641 faces are closed parts; the first open one is named
glass PLY/Wuson.ply "a refractive part is not closed: 60 faces of material 0 (unnamed) from \
face 1642,"
glass OBJ/spider.obj "a refractive part is not closed: 90 faces of material 'Skin' from face 61,"

# A real model is not mirrored (issue 49): regr01.obj (2,710 triangles, no normals, an asymmetric
# building) renders bit for bit as its faces written as `triangle` lines converted by hand into
# trazador's left-handed space (tests/obj_to_scene.awk), and unlike its mirror image.
handed() {
    local file=$models/OBJ/regr01.obj view
    view='camera position 624 381 -2500 direction 0 0 1 up 0 1 0 fov 40
plane width 64 height 48 pixel 1
light position 624 1500 -2000 power 4000000'
    printf '%s\nmesh lambertian file %s\n' "$view" "$file" >"$tmp/handed_file.scene"
    { echo "$view"; awk -f "$here/obj_to_scene.awk" "$file"; } >"$tmp/handed_hand.scene"
    { echo "$view"; awk -v mirror=1 -f "$here/obj_to_scene.awk" "$file"; } \
        >"$tmp/handed_mirror.scene"
    local k
    for k in file hand mirror; do
        "$tz" render "$tmp/handed_$k.scene" --backend cpu --spp 1 --quiet \
            -o "$tmp/handed_$k.pfm" 2>/dev/null || fail "regr01.obj: the $k scene not rendered"
    done
    cmp -s "$tmp/handed_file.pfm" "$tmp/handed_hand.pfm" ||
        fail "regr01.obj: not the faces converted by hand into the left-handed space"
    cmp -s "$tmp/handed_file.pfm" "$tmp/handed_mirror.pfm" &&
        fail "regr01.obj: renders as its mirror image"
    return 0
}
handed

# refused FILE: exit 2, the error at the mesh directive's file key, the old output kept.
refused() {
    local file=$1 out rc=0
    scene_for "$file" 3 >"$tmp/bad.scene"
    printf 'an earlier image\n' >"$tmp/kept.ppm"
    out=$("$tz" render "$tmp/bad.scene" --backend cpu --spp 1 -o "$tmp/kept.ppm" 2>&1) || rc=$?
    [ $rc = 2 ] || fail "$file: exit $rc, expected 2"
    grep -q "^$tmp/bad.scene:4:11: mesh '$models/$file': " <<<"$out" ||
        fail "$file: no file:line:col error: $out"
    [ "$(cat "$tmp/kept.ppm")" = "an earlier image" ] || fail "$file: the old output was touched"
}

refused invalid/empty.obj
refused invalid/empty.ply
refused invalid/empty.3ds
refused invalid/malformed.obj
refused invalid/OutOfMemory.off
refused invalid/readme.txt

# A model file as the scene (issue 51): its cameras and point lights converted into trazador's
# space (the node's transform in the file's right-handed space, then z negated), each image the
# bits of a scene written by hand with the camera and lights converted here. Path mode, CPU.
cameras=$models/glTF2/cameras/Cameras.gltf
# same NAME A B: two renders wrote the very same file.
same() { cmp -s "$2" "$3" && return 0; fail "$1: the model's image is not the hand-converted scene's"; }
render_quiet() { "$tz" render "$@" --backend cpu --spp 2 --quiet 2>"$tmp/err"; }
# Cameras.gltf's camera 0: node translation 0.5 0.5 3, looking along -z (glTF's), up +y; yfov
# 0.7 rad at aspect 1: a horizontal fov of 2 atan(1 tan(0.7 / 2)) = 40.1070442 degrees (float).
{
    printf 'camera position 0.5 0.5 -3 direction 0 0 1 up 0 1 0 fov 40.1070442\n'
    printf 'plane width 32 height 32 pixel 1\nmesh file %s\nbackground 1 1 1\n' "$cameras"
    printf 'render mode path\n'
} >"$tmp/cam0.scene"
render_quiet "$cameras" --width 32 -o "$tmp/model.pfm" || fail "Cameras.gltf: exit $?: $(cat "$tmp/err")"
render_quiet "$tmp/cam0.scene" -o "$tmp/hand0.pfm" || fail "cam0.scene: $(cat "$tmp/err")"
same "Cameras.gltf camera 0" "$tmp/model.pfm" "$tmp/hand0.pfm"
render_quiet "$cameras" --camera 0 --width 32 -o "$tmp/model0.pfm" && same "--camera 0" "$tmp/model.pfm" "$tmp/model0.pfm"
# `trazador info` lists the cameras as converted
"$tz" info "$cameras" >"$tmp/info" || fail "info Cameras.gltf: exit $?"
grep -qF "camera 0 'nodes[1]': at 0.5 0.5 -3 looking along 0 0 1, up 0 1 0, fov 40.107, aspect 1" \
    "$tmp/info" || fail "info Cameras.gltf: $(cat "$tmp/info")"
grep -qF "camera 1 'nodes[2]': orthographic" "$tmp/info" || fail "info Cameras.gltf: $(cat "$tmp/info")"
# expect_refusal NAME WANT ARGS...: exit 2 with WANT in the message.
expect_refusal() {
    local name=$1 want=$2 rc=0
    shift 2
    "$tz" render "$@" --backend cpu --spp 1 -o "$tmp/refused.pfm" >"$tmp/out" 2>&1 || rc=$?
    [ $rc = 2 ] || fail "$name: exit $rc, expected 2: $(cat "$tmp/out")"
    grep -qF -- "$want" "$tmp/out" || fail "$name: '$want' not in: $(cat "$tmp/out")"
}
# Its camera 1 is orthographic, xmag = ymag = 1 at the same node: a view 2 x 2 along +z, 32
# pixels of 0.0625 across.
{
    printf 'camera position 0.5 0.5 -3 direction 0 0 1 up 0 1 0 projection orthographic\n'
    printf 'plane width 2 height 2 pixel 0.0625\nmesh file %s\nbackground 1 1 1\n' "$cameras"
    printf 'render mode path\n'
} >"$tmp/cam1.scene"
render_quiet "$cameras" --camera 1 --width 32 -o "$tmp/model1.pfm" || fail "Cameras.gltf --camera 1: exit $?: $(cat "$tmp/err")"
render_quiet "$tmp/cam1.scene" -o "$tmp/hand1.pfm" || fail "cam1.scene: $(cat "$tmp/err")"
same "Cameras.gltf camera 1 (orthographic)" "$tmp/model1.pfm" "$tmp/hand1.pfm"
expect_refusal "--camera 5" "Cameras.gltf: --camera 5: the file has 2 cameras: 0 'nodes[1]', 1 'nodes[2]' (orthographic)" "$cameras" --camera 5
expect_refusal "--camera of a scene" "--camera picks a camera of a model file" "$tmp/cam0.scene" --camera 0
expect_refusal "--environment of a scene" "--environment lights a model file" "$tmp/cam0.scene" --environment "$here/../scenes/maps/sky.exr"
# gltf_with CAMERA_NODE CAMERA LIGHTS LIGHT_NODES: the square of Cameras.gltf, a camera on a
# node of its own and point lights on nodes under a parent moved up by 1.
cp "$models/glTF2/cameras/simpleSquare.bin" "$tmp/"
gltf_with() {
    printf '{"asset":{"version":"2.0"},"extensionsUsed":["KHR_lights_punctual"],\n'
    printf '"extensions":{"KHR_lights_punctual":{"lights":[%s]}},\n' "$3"
    printf '"scenes":[{"nodes":[0,1,2]}],\n'
    printf '"nodes":[{"mesh":0},{"name":"eye",%s,"camera":0},{"translation":[0,1,0],"children":[%s]}%s],\n' \
        "$1" "$4" "$5"
    printf '"cameras":[{"type":"perspective","perspective":%s}],\n' "$2"
    printf '"meshes":[{"primitives":[{"attributes":{"POSITION":1},"indices":0}]}],\n'
    printf '"buffers":[{"uri":"simpleSquare.bin","byteLength":60}],\n'
    printf '"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":12},{"buffer":0,"byteOffset":12,"byteLength":48}],\n'
    printf '"accessors":[{"bufferView":0,"componentType":5123,"count":6,"type":"SCALAR"},'
    printf '{"bufferView":1,"componentType":5126,"count":4,"type":"VEC3","max":[1,1,0],"min":[0,0,0]}]}\n'
}
# A camera turned half round about y at 0.5 0.5 -3 (the file's), aspect 2: trazador's 0.5 0.5 3
# looking along -z (assimp 5.2.5 alone doubles the translation, and turns the square's back
# away); 2 atan(2 tan(0.35)) = 72.2631454 degrees; 32 x 16 pixels. A point light of colour
# 1 0.5 0.25 and 40 candela at 0.5 1 -1 under the parent's 0 1 0: trazador's 0.5 2 1, power 40.
gltf_with '"translation":[0.5,0.5,-3],"rotation":[0,1,0,0]' '{"aspectRatio":2.0,"yfov":0.7,"znear":0.01}' \
    '{"type":"point","color":[1,0.5,0.25],"intensity":40}' 3 \
    ',{"name":"lamp","translation":[0.5,1,-1],"extensions":{"KHR_lights_punctual":{"light":0}}}' >"$tmp/lit.gltf"
{
    printf 'camera position 0.5 0.5 3 direction 0 0 -1 up 0 1 0 fov 72.2631454\n'
    printf 'plane width 32 height 16 pixel 1\nlight position 0.5 2 1 power 40 color 1 0.5 0.25\n'
    printf 'mesh file %s\nrender mode path\n' "$tmp/lit.gltf"
} >"$tmp/lit.scene"
# like_hand NAME MODEL SCENE: the model as the scene, 32 pixels across, renders the bits of the
# scene written by hand (into model.pfm and hand.pfm), and not black.
like_hand() {
    render_quiet "$2" --width 32 -o "$tmp/model.pfm" || fail "$1: exit $?: $(cat "$tmp/err")"
    render_quiet "$3" -o "$tmp/hand.pfm" || fail "$1, by hand: $(cat "$tmp/err")"
    same "$1" "$tmp/model.pfm" "$tmp/hand.pfm"
    "$tz" diff "$tmp/model.pfm" "$tmp/black.pfm" >/dev/null 2>&1 && fail "$1: rendered black" || true
}
like_hand "a turned camera and a point light" "$tmp/lit.gltf" "$tmp/lit.scene"
cp "$tmp/model.pfm" "$tmp/lit.pfm"
# --environment lights the model by a map beside its lights: the scene with that environment
# line, bit for bit; a scene file is refused it (its environment line says what lights it).
sky="$here/../scenes/maps/sky.exr"
render_quiet "$tmp/lit.gltf" --width 32 --environment "$sky" -o "$tmp/model.pfm" ||
    fail "lit.gltf --environment: exit $?: $(cat "$tmp/err")"
{
    cat "$tmp/lit.scene"
    printf 'environment file "%s"\n' "$sky"
} >"$tmp/lit_env.scene"
render_quiet "$tmp/lit_env.scene" -o "$tmp/hand.pfm" || fail "lit_env.scene: $(cat "$tmp/err")"
same "--environment" "$tmp/model.pfm" "$tmp/hand.pfm"
cmp -s "$tmp/model.pfm" "$tmp/lit.pfm" && fail "--environment: the map changed nothing" || true
# In a scene: `camera file` takes the file's camera and `mesh ... lights on` its point lights,
# both moved by the line's transform: the hand-converted scene moved by 1 along x.
{
    printf 'camera file %s index 0 translate 1 0 0
' "$tmp/lit.gltf"
    printf 'plane width 32 height 16 pixel 1
mesh file %s lights on translate 1 0 0
' "$tmp/lit.gltf"
    printf 'render mode path
'
} >"$tmp/moved.scene"
sed 's/^camera position 0.5 /camera position 1.5 /; s/^light position 0.5 /light position 1.5 /; s/^\(mesh file .*\)$/\1 translate 1 0 0/' \
    "$tmp/lit.scene" >"$tmp/moved_hand.scene"
render_quiet "$tmp/moved.scene" -o "$tmp/model.pfm" || fail "moved.scene: exit $?: $(cat "$tmp/err")"
render_quiet "$tmp/moved_hand.scene" -o "$tmp/hand.pfm" || fail "moved_hand.scene: $(cat "$tmp/err")"
same "camera file and lights on, translated" "$tmp/model.pfm" "$tmp/hand.pfm"
printf 'camera file %s name eye
plane width 32 height 32 pixel 1
mesh file %s
background 1 1 1
render mode path
' \
    "$cameras" "$cameras" | sed 's/name eye/index 0/' >"$tmp/cam0_file.scene"
render_quiet "$tmp/cam0_file.scene" -o "$tmp/model.pfm" || fail "cam0_file.scene: $(cat "$tmp/err")"
same "camera file Cameras.gltf" "$tmp/model.pfm" "$tmp/hand0.pfm"
printf 'camera file %s name nobody
plane width 8 height 8 pixel 1
' "$cameras" >"$tmp/nobody.scene"
expect_refusal "camera file name" "camera file '$cameras' has 2 cameras: 0 'nodes[1]', 1 'nodes[2]'" "$tmp/nobody.scene"
# bad input: a light of negative intensity (named), a camera of aspect 0
gltf_with '"translation":[0.5,0.5,3]' '{"aspectRatio":1.0,"yfov":0.7}' \
    '{"type":"point","intensity":-5}' 3 \
    ',{"name":"lamp","extensions":{"KHR_lights_punctual":{"light":0}}}' >"$tmp/dark.gltf"
expect_refusal "negative light" "dark.gltf: light 0 'lamp' (point) has colour x intensity -5 -5 -5" "$tmp/dark.gltf"
gltf_with '"translation":[0.5,0.5,3]' '{"aspectRatio":0,"yfov":0.7}' '{"type":"point"}' 3 \
    ',{"extensions":{"KHR_lights_punctual":{"light":0}}}' >"$tmp/flat.gltf"
expect_refusal "aspect 0" "flat.gltf: camera 0 'eye' has an aspect ratio of 0" "$tmp/flat.gltf"
# A spot light (cone 0.3 to 0.6 rad, 30 candela, white) and a directional light (2 lux, colour
# 1 0.5 0.25), each on a node turned half round about y under the parent's 0 1 0: both travel
# along trazador's 0 0 -1, the spot from 0.5 2 1; the cone in degrees of the angles' floats.
gltf_with '"translation":[0.5,0.5,-3],"rotation":[0,1,0,0]' '{"aspectRatio":2.0,"yfov":0.7}' \
    '{"type":"spot","intensity":30,"spot":{"innerConeAngle":0.3,"outerConeAngle":0.6}},{"type":"directional","color":[1,0.5,0.25],"intensity":2}' \
    '3,4' ',{"name":"cone","translation":[0.5,1,-1],"rotation":[0,1,0,0],"extensions":{"KHR_lights_punctual":{"light":0}}},{"name":"sky","rotation":[0,1,0,0],"extensions":{"KHR_lights_punctual":{"light":1}}}' >"$tmp/spot.gltf"
{
    printf 'camera position 0.5 0.5 3 direction 0 0 -1 up 0 1 0 fov 72.2631454\n'
    printf 'plane width 32 height 16 pixel 1\n'
    printf 'light position 0.5 2 1 power 30 direction 0 0 -1 cone 17.188734536943613 34.377469073887227\n'
    printf 'sun direction 0 0 -1 irradiance 2 color 1 0.5 0.25 angle 0\n'
    printf 'mesh file %s\nrender mode path\n' "$tmp/spot.gltf"
} >"$tmp/spot.scene"
like_hand "a spot and a directional light" "$tmp/spot.gltf" "$tmp/spot.scene"
# a second directional light is warned of by name (a scene has one sun)
gltf_with '"translation":[0.5,0.5,3]' '{"aspectRatio":1.0,"yfov":0.7}' \
    '{"type":"directional"},{"type":"directional"}' 3,4 \
    ',{"name":"one","extensions":{"KHR_lights_punctual":{"light":0}}},{"name":"two","extensions":{"KHR_lights_punctual":{"light":1}}}' >"$tmp/suns.gltf"
"$tz" render "$tmp/suns.gltf" --backend cpu --spp 1 --width 8 -o "$tmp/suns.pfm" 2>"$tmp/err" ||
    fail "suns.gltf: exit $?"
grep -qF "its directional light 'two' (a second sun) is not rendered" "$tmp/err" ||
    fail "suns.gltf: no warning naming the second sun: $(cat "$tmp/err")"
# a spot whose cone is wider than a hemisphere is refused, named
gltf_with '"translation":[0.5,0.5,3]' '{"aspectRatio":1.0,"yfov":0.7}' \
    '{"type":"spot","spot":{"innerConeAngle":0.1,"outerConeAngle":2}}' 3 \
    ',{"name":"wide","extensions":{"KHR_lights_punctual":{"light":0}}}' >"$tmp/wide.gltf"
expect_refusal "wide spot" "spot light 0 'wide' has a cone of 0.1 to 2 radians" "$tmp/wide.gltf"
# No camera: one framing the box (scenes/README.md's rule): from its centre c along (1, 1, -1),
# d = r / sin(min(fov, vertical fov) / 2), r half the diagonal, fov 50, 4:3. A triangle's box is
# 0 0 0 to 1 1 0 (z negated: 0); 32 x 24 pixels.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$tmp/tri.obj"
awk -v f="$tmp/tri.obj" 'BEGIN {
    pi = atan2(0, -1); h = 50 * pi / 360; v = atan2(sin(h) / cos(h) * 24 / 32, 1)
    r = 0.5 * sqrt(2); d = r / sin(h < v ? h : v); k = d / sqrt(3)
    printf "camera position %.9g %.9g %.9g look_at 0.5 0.5 0 fov 50\n", 0.5 + k, 0.5 + k, -k
    printf "plane width 32 height 24 pixel 1\nmesh file %s lights on\nbackground 1 1 1\nrender mode path\n", f
}' >"$tmp/framed.scene"
render_quiet "$tmp/tri.obj" --width 32 -o "$tmp/model.pfm" || fail "tri.obj: exit $?: $(cat "$tmp/err")"
render_quiet "$tmp/framed.scene" -o "$tmp/hand.pfm" || fail "framed.scene: $(cat "$tmp/err")"
"$tz" diff "$tmp/model.pfm" "$tmp/hand.pfm" --max-rmse 0.001 >/dev/null ||
    fail "tri.obj: not framed by the documented rule: $("$tz" diff "$tmp/model.pfm" "$tmp/hand.pfm" 2>&1)"
# shared FILE DISTANCE INSTANCES: a file whose nodes place one mesh several times keeps it once,
# with INSTANCES instances (`trazador info`, `--verbose`), is seen, and agrees across back ends.
shared() {
    local file=$1 distance=$2 instances=$3 out
    out=$("$tz" info "$models/$file" 2>&1) || fail "$file: no info: $out"
    grep -q "meshes that $instances instances share" <<<"$out" ||
        fail "$file: expected $instances instances: $out"
    scene_for "$file" "$distance" >"$tmp/model.scene"
    if ! "$tz" render "$tmp/model.scene" --backend cpu --spp 1 --verbose -o "$tmp/cpu.pfm" \
        >"$tmp/err" 2>&1; then
        fail "$file: not rendered: $(tail -1 "$tmp/err")"
        return
    fi
    grep -q "meshes that $instances instances share), bounding box" "$tmp/err" ||
        fail "$file: --verbose does not count $instances instances"
    seen_and_agrees "$file"
}

shared glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb 600 100
shared glTF/CesiumMilkTruck/CesiumMilkTruck.gltf 8 2
shared glTF2/textureTransform/TextureTransformTest.gltf 3 5
shared Collada/teapot_instancenodes.DAE 8 2

# Every glTF, OBJ and PLY of assimp-testmodels given as the scene: an image (exit 0) or a
# message (exit 2), never a crash or a hang.
while IFS= read -r -d '' file; do
    rc=0
    timeout 60 "$tz" render "$file" --backend cpu --spp 1 --width 16 -o "$tmp/any.pfm" \
        >"$tmp/out" 2>&1 || rc=$?
    if [ $rc = 2 ]; then
        [ -s "$tmp/out" ] || fail "$file: exit 2 without a message"
    elif [ $rc != 0 ]; then
        fail "$file as the scene: exit $rc: $(tail -c 300 "$tmp/out")"
    fi
done < <(find "$models" \( -iname '*.gltf' -o -iname '*.glb' -o -iname '*.obj' -o -iname '*.ply' \) -print0 | sort -z)

[ $failures = 0 ] || exit 1
echo "models: all passed"
