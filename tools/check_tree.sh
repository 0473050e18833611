#!/usr/bin/env bash
# tools/check_tree.sh: two checks of the tree that cannot pass by accident (run by .ci/run):
# every repository path that README.md, docs/ and the source comments name exists, and
# clang-format (.clang-format) would change no C file or shared C/GLSL header.
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
[ "$failed" = 0 ] && echo "check_tree: every named path exists; clang-format changes nothing"
exit "$failed"
