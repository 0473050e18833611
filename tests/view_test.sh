#!/usr/bin/env bash
# view_test.sh TRAZADOR SOURCE_DIR: `trazador view` in a window of its own Xvfb, on the CPU back
# end and on Vulkan (lavapipe in CI): once the title says the samples asked for are done, a
# screenshot of the window is byte for byte `render` of the same scene at those samples; a
# scripted orbit, pan and wheel move the camera, and the camera line the c key prints renders
# the moved view (the screenshot again); the m key switches to path mode, the same again; + and -
# change the exposure and back; the s key writes a PNG and a part that `merge` and `render
# --resume` take. Without a display, view says so in one line and exits 2. Exit 77 (skip) only
# where Xvfb, xdotool or ImageMagick's import is missing (Debian: xvfb, xdotool, imagemagick;
# .ci/run installs them).
set -u
tz=$(realpath "$1")
src=$(realpath "$2")
for tool in Xvfb xdotool import convert; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        echo "view_test: $tool is not installed (Debian: xvfb, xdotool, imagemagick); skipped"
        exit 77
    fi
done
source "$(dirname "$0")/check.sh"
cp "$src/scenes/cornell.scene" .
# 200 x 200 pixels: a chunk of 16 samples takes a fraction of a second on either back end.
size="--width 200"

one_line() { # one_line NAME: $tmp/err is one line (LeakSanitizer's count of suppressions apart)
    local lines
    lines=$(grep -cv -e '^-*$' -e '^Suppressions used:' -e 'count *bytes template' \
        -e '^ *[0-9][0-9]* *[0-9][0-9]* [^ ]*$' "$tmp/err")
    [ "$lines" = 1 ] && ok || bad "$1: more than one line: $(cat "$tmp/err")"
}
run "no display" 2 env -u DISPLAY -u WAYLAND_DISPLAY "$tz" view cornell.scene $size
has "no display" "$tmp/err" "trazador: view: no display"
one_line "no display"
# A display no server holds: one line too.
if [ ! -e /tmp/.X11-unix/X999 ]; then
    run "no server" 2 env DISPLAY=:999 "$tz" view cornell.scene $size
    has "no server" "$tmp/err" "trazador: view: cannot open the display ':999'"
    one_line "no server"
fi

# A display number no server holds (another may take it first: then the next); -noreset keeps
# the server up between windows.
display= xvfb=
for n in $(seq 71 170); do
    { [ -e "/tmp/.X11-unix/X$n" ] || [ -e "/tmp/.X$n-lock" ]; } && continue
    Xvfb ":$n" -screen 0 640x480x24 -nolisten tcp -noreset >xvfb.log 2>&1 &
    server=$!
    for _ in $(seq 1 100); do
        kill -0 "$server" 2>/dev/null || break
        DISPLAY=":$n" xdotool getmouselocation >/dev/null 2>&1 && display=$n && break
        sleep 0.1
    done
    [ -n "$display" ] && xvfb=$server && break
    kill "$server" 2>/dev/null
done
if [ -z "$display" ]; then
    echo "view_test: no Xvfb started on a free display: $(cat xvfb.log)" >&2
    exit 1
fi
trap 'kill $xvfb 2>/dev/null; rm -rf "$tmp"' EXIT
export DISPLAY=":$display"

view_pid= window=
start_view() { # start_view ARGS...: the view in the background, its window in $window
    "$tz" view cornell.scene $size --save-as saved "$@" >view.out 2>view.err &
    view_pid=$!
    window=
    for _ in $(seq 1 300); do
        window=$(xdotool search --onlyvisible --pid "$view_pid" --name '^trazador view' 2>/dev/null |
            head -1)
        [ -n "$window" ] && break
        sleep 0.1
    done
    # Keys go to the window with the focus; --sync waits for it, and would wait for ever on a
    # window not yet mapped.
    [ -n "$window" ] && timeout 10 xdotool windowfocus --sync "$window" 2>/dev/null
}
title=
wait_done() { # wait_done NAME [TEXT]: until the title says the samples asked for are done (and TEXT)
    title=
    for _ in $(seq 1 600); do
        title=$(xdotool getwindowname "$window" 2>/dev/null)
        case $title in *"(done)"*"${2:-}"*) ok; return 0 ;; esac
        sleep 0.1
    done
    bad "$1: the title never said done: '$title'; $(cat view.err)"
    return 1
}
wait_line() { # wait_line NAME COUNT TEXT: until view.out holds COUNT lines with TEXT
    for _ in $(seq 1 300); do
        [ "$(grep -c -- "$3" view.out)" -ge "$2" ] && { ok; return 0; }
        sleep 0.1
    done
    bad "$1: no line '$3' in the view's output: $(cat view.out)"
    return 1
}
shows() { # shows NAME IMAGE: the window's pixels are IMAGE's
    import -window "$window" shot.png && convert shot.png -alpha off PNG24:shown.png
    if "$tz" diff shown.png "$2" >diff.out 2>&1; then ok; else
        bad "$1: the window differs from $2: $(cat diff.out)"
    fi
}
quit_view() { # quit_view NAME: Escape closes the view, exit 0 (within 30 s, else killed)
    xdotool key --clearmodifiers Escape
    for _ in $(seq 1 300); do kill -0 "$view_pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$view_pid" 2>/dev/null; then
        kill "$view_pid"
        bad "$1: Escape did not close the view"
    fi
    wait "$view_pid"
    local rc=$?
    [ "$rc" = 0 ] && ok || bad "$1: view exited $rc: $(cat view.err)"
}
with_camera() { # with_camera LINE OUT: cornell.scene with its camera line replaced by LINE
    sed "s|^camera .*|$1|" cornell.scene >"$2"
}

backends=cpu
if "$tz" devices >/dev/null 2>&1; then backends="cpu vulkan"; else
    echo "view_test: no Vulkan device; the view runs on the CPU back end only"
fi
for backend in $backends; do
    spp=32
    [ "$backend" = vulkan ] && spp=16 # lavapipe: a chunk of 16 is enough to tell
    render="render $size --backend $backend --spp $spp --quiet"
    "$tz" $render cornell.scene -o ref.png
    start_view --backend "$backend" --spp "$spp"
    wait_done "$backend first" && shows "${backend}_first" ref.png
    case $title in *"$spp of $spp spp (done) | "*" Msamples/s | $backend | report mode"*) ok ;;
    *) bad "$backend: the title lacks the samples, the rate or the back end: '$title'" ;; esac
    # s: the image and its part; the part merges, and resumes, to the render's image.
    xdotool key s
    wait_line "$backend save" 1 "saved saved-1.png and saved-1.exr"
    run "$backend saved png" 0 "$tz" diff saved-1.png ref.png
    run "$backend merge saved" 0 "$tz" merge saved-1.exr -o merged.png --quiet
    run "$backend merged" 0 "$tz" diff merged.png ref.png
    run "$backend resume saved" 0 "$tz" $render cornell.scene --resume saved-1.exr -o resumed.png
    run "$backend resumed" 0 "$tz" diff resumed.png ref.png
    # An orbit (left drag), a pan (right drag) and a wheel step; c prints the camera then.
    xdotool mousemove --window "$window" 100 100 mousedown 1 mousemove --window "$window" 130 110 \
        mousemove --window "$window" 150 120 mouseup 1
    xdotool mousemove --window "$window" 100 100 mousedown 3 mousemove --window "$window" 90 95 \
        mouseup 3
    xdotool click 4
    xdotool key c
    wait_line "$backend camera" 1 "^camera position"
    line=$(grep "^camera position" view.out | tail -1)
    case $line in *"position 0 0 -9.5 direction 0 0 1 "*) bad "$backend: the camera did not move: $line" ;; *) ok ;; esac
    with_camera "$line" moved.scene
    "$tz" $render moved.scene -o moved.png
    wait_done "$backend moved" && shows "${backend}_moved" moved.png
    if [ "$backend" = cpu ]; then # m: path mode, the same camera
        xdotool key m
        wait_done "$backend path" "path mode" && {
            "$tz" $render moved.scene --mode path -o path.png 2>/dev/null
            shows "${backend}_path" path.png
            # + brightens the window by half a stop, - takes it back to render's bytes.
            xdotool key plus
            wait_done "$backend exposure" "exposure +0.5" && {
                import -window "$window" shot.png && convert shot.png -alpha off PNG24:bright.png
                run "$backend brighter" 1 "$tz" diff bright.png path.png
            }
            xdotool key minus
            wait_done "$backend exposure back" "exposure +0.0" && shows "${backend}_back" path.png
        }
    fi
    quit_view "$backend"
    rm -f saved-*
done
check_summary view_test
