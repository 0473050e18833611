#!/bin/sh
# build.sh [--tests]: installs the Debian packages trazador needs when they are missing (as root,
# or through sudo), then configures and builds a release build in build/. --tests also installs
# what the test suite runs beyond the renderer (tests/slurm_test.sh: Slurm and munge;
# tests/parallel_test.sh: GNU parallel; tests/models_test.sh: Debian's real models;
# tests/view_test.sh: a virtual X server, xdotool and ImageMagick), so that `ctest` skips nothing
# (the slurm test also needs root).
# TRAZADOR_MESA=backports also installs lavapipe of Mesa 25 (mesa-vulkan-drivers and the libdrm
# it needs) from Debian's bookworm-backports, adding that suite to the machine's apt sources on
# the URI of its own Debian source (README, "lavapipe"); the default, system, keeps the driver
# the machine has.
set -eu
cd "$(dirname "$0")"
tests=false
for arg in "$@"; do
    case $arg in
        --tests) tests=true ;;
        *)
            echo "build.sh: usage: build.sh [--tests], got '$arg'" >&2
            exit 2
            ;;
    esac
done
mesa=${TRAZADOR_MESA:-system}
case $mesa in
    system | backports) ;;
    *)
        echo "build.sh: TRAZADOR_MESA is system or backports, got '$mesa'" >&2
        exit 2
        ;;
esac
sudo=""
[ "$(id -u)" = 0 ] || sudo=sudo
packages="build-essential cmake pkg-config libvulkan-dev mesa-vulkan-drivers glslang-tools
vulkan-validationlayers libpng-dev libjpeg62-turbo-dev libopenexr-dev libassimp-dev libsdl2-dev libstb-dev spirv-tools"
$tests && packages="$packages slurmctld slurmd slurm-client munge parallel assimp-testmodels
xvfb xdotool imagemagick"
missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    echo "build.sh: installing$missing"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends $missing
fi
if [ "$mesa" = backports ] &&
    ! dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null | grep -q '~bpo'; then
    # The suite is added once, beside the machine's own source and on its URI (its mirror);
    # backports are never taken unless named, so nothing else changes on upgrades.
    if ! grep -hsv '^[[:space:]]*#' /etc/apt/sources.list /etc/apt/sources.list.d/*.list \
        /etc/apt/sources.list.d/*.sources | grep -qw bookworm-backports; then
        uri=$(tools/debian_uri.sh)
        list=/etc/apt/sources.list.d/trazador-bookworm-backports.sources
        echo "build.sh: adding bookworm-backports ($uri) as $list"
        printf 'Types: deb\nURIs: %s\nSuites: bookworm-backports\nComponents: main\nSigned-By: %s\n' \
            "$uri" /usr/share/keyrings/debian-archive-keyring.gpg | $sudo tee "$list" >/dev/null
    fi
    echo "build.sh: installing lavapipe (mesa-vulkan-drivers) and libdrm from bookworm-backports"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends \
        mesa-vulkan-drivers/bookworm-backports libdrm2/bookworm-backports
fi
# Warnings are errors in CI (CI=true), plain warnings elsewhere.
werror=OFF
[ "${CI:-}" = true ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DTRAZADOR_WERROR=$werror >/dev/null
cmake --build build -j "$(nproc)"
