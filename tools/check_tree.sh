#!/usr/bin/env bash
# tools/check_tree.sh: three checks of the tree that cannot pass by accident (run by .ci/run):
# every repository path that README.md, docs/ and the source comments name exists; clang-format
# (.clang-format) would change no C file or shared C/GLSL header; and no source includes a
# header by a path relative to its own folder, which the compiler would find without the layer
# folders of cmake/Layers.cmake (docs/DESIGN.md section 1) and so without their rules.
set -uo pipefail
cd "$(dirname "$0")/.."
failed=0
# Paths: words that start with one of the tree's folders and end in a file name or a slash.
folders='src|shaders|tests|docs|scenes|tools|cmake|\.ci'
missing=$(grep -rhoE "(^|[^A-Za-z0-9_./$}-])($folders)/[A-Za-z0-9_./*-]*[A-Za-z0-9_*/]" \
    README.md docs/*.md scenes/README.md tools/slurm/README.md src shaders tests tools \
    CMakeLists.txt cmake 2>/dev/null |
    sed -E "s/^[^A-Za-z.]//" | sort -u |
    while read -r path; do
        case $path in *'*'*) compgen -G "$path" >/dev/null || echo "$path" ;;
        *) [ -e "$path" ] || echo "$path" ;; esac
    done)
if [ -n "$missing" ]; then
    echo "check_tree: paths named in the docs or the sources that do not exist:" >&2
    echo "$missing" | sed 's/^/  /' >&2
    failed=1
fi
files=$(git ls-files '*.c' '*.h')
if ! clang-format --dry-run --Werror $files 2>/tmp/check_tree_format.$$; then
    echo "check_tree: clang-format would change:" >&2
    grep -oE "^[^: ]+\.(c|h):" /tmp/check_tree_format.$$ | sort -u | sed 's/^/  /' >&2
    failed=1
fi
rm -f /tmp/check_tree_format.$$
relative=$(for file in $(git ls-files src | grep -E '\.[ch]$'); do
    grep -oE '^#include "[^"]+"' "$file" | sed -E 's/^#include "(.*)"/\1/' |
        while read -r header; do
            [ -e "$(dirname "$file")/$header" ] && echo "$file: $header"
        done
done)
if [ -n "$relative" ]; then
    echo "check_tree: includes relative to the including file's folder (name the layer):" >&2
    echo "$relative" | sed 's/^/  /' >&2
    failed=1
fi
[ "$failed" = 0 ] &&
    echo "check_tree: every named path exists; clang-format changes nothing; includes name layers"
exit "$failed"
