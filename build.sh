#!/bin/sh
# build.sh: installs the Debian packages trazador needs when they are missing (as root, or
# through sudo), then configures and builds a release build in build/.
set -eu
cd "$(dirname "$0")"
packages="build-essential cmake pkg-config libvulkan-dev mesa-vulkan-drivers glslang-tools
vulkan-validationlayers libpng-dev libopenexr-dev libassimp-dev"
missing=""
for p in $packages; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
    sudo=""
    [ "$(id -u)" = 0 ] || sudo=sudo
    echo "build.sh: installing$missing"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends $missing
fi
# Warnings are errors in CI (CI=true), plain warnings elsewhere.
werror=OFF
[ "${CI:-}" = true ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DTRAZADOR_WERROR=$werror >/dev/null
cmake --build build -j "$(nproc)"
