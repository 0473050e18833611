#!/bin/sh
# tools/mesa25.sh [DIR]: unpacks lavapipe from Debian's bookworm-backports (mesa-vulkan-drivers
# 25.0 and the libdrm2 it needs) into DIR (default build/mesa25) without installing anything, and
# writes DIR/lvp_icd.json and DIR/env.sh, so that a run selects that driver instead of the
# system's:  . build/mesa25/env.sh && ctest --test-dir build -L vulkan
# apt runs on a private list and cache in DIR (the machine's apt state is not touched), on the
# URIs of the machine's own Debian source. Needs apt-get, dpkg-deb and the network; not root.
set -eu
dir=${1:-$(dirname "$0")/../build/mesa25}
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
cd "$(dirname "$0")/.."
suite=bookworm-backports

uri=$(tools/debian_uri.sh)

apt="$dir/apt"
mkdir -p "$apt/lists/partial" "$apt/cache/archives/partial" "$dir/deb"
keyring=/usr/share/keyrings/debian-archive-keyring.gpg
echo "deb [signed-by=$keyring] $uri $suite main" >"$apt/sources.list"
# As root apt downloads as the _apt user, who cannot write into a build folder; root keeps it.
sandbox=""
[ "$(id -u)" = 0 ] && sandbox="-o APT::Sandbox::User=root"
apt_opts="-q -o Dir::Etc::SourceList=$apt/sources.list -o Dir::Etc::SourceParts=/nonexistent
-o Dir::State::Lists=$apt/lists -o Dir::Cache=$apt/cache $sandbox"
# shellcheck disable=SC2086 # apt_opts is a list of words
apt-get $apt_opts update >"$apt/update.log" 2>&1 || {
    cat "$apt/update.log" >&2
    exit 1
}
rm -f "$dir"/deb/*.deb
# shellcheck disable=SC2086
(cd "$dir/deb" && apt-get $apt_opts download mesa-vulkan-drivers/$suite libdrm2/$suite)
rm -rf "$dir/root"
for deb in "$dir"/deb/*.deb; do dpkg-deb -x "$deb" "$dir/root"; done

lib="$dir/root/usr/lib/x86_64-linux-gnu"
lvp="$lib/libvulkan_lvp.so"
if [ ! -f "$lvp" ]; then
    echo "tools/mesa25.sh: the package holds no $lvp" >&2
    exit 1
fi
api=$(sed -n 's/.*"api_version": *"\([0-9.]*\)".*/\1/p' "$dir/root/usr/share/vulkan/icd.d/lvp_icd.json")
cat >"$dir/lvp_icd.json" <<EOF
{
    "ICD": {
        "api_version": "${api:-1.3.0}",
        "library_path": "$lvp"
    },
    "file_format_version": "1.0.0"
}
EOF
cat >"$dir/env.sh" <<EOF
# Selects the unpacked lavapipe of $suite (tools/mesa25.sh); source it: . $dir/env.sh
export VK_DRIVER_FILES=$dir/lvp_icd.json
export VK_ICD_FILENAMES=$dir/lvp_icd.json
export LD_LIBRARY_PATH=$lib\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}
EOF
# What the driver needs beyond the two packages must be on the machine already (Debian 12's
# mesa-vulkan-drivers brings the same libraries: LLVM 15, xcb, wayland, zstd).
missing=$(LD_LIBRARY_PATH=$lib ldd "$lvp" | awk '/not found/ { print $1 }')
if [ -n "$missing" ]; then
    echo "tools/mesa25.sh: $lvp needs libraries this machine lacks: $missing" >&2
    exit 1
fi
version=$(dpkg-deb -f "$(ls "$dir"/deb/mesa-vulkan-drivers_*.deb)" Version)
echo "tools/mesa25.sh: lavapipe $version in $dir (. $dir/env.sh selects it)"
