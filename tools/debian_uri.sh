#!/bin/sh
# tools/debian_uri.sh: prints the URI of the machine's own Debian bookworm source (the first
# deb822 stanza in /etc/apt/sources.list.d/*.sources whose suites include bookworm, else the
# first one-line `deb URI bookworm ...` of sources.list), so that build.sh and tools/mesa25.sh
# reach bookworm-backports through the mirror the machine already uses. Exits 1 when none.
set -eu
for f in /etc/apt/sources.list.d/*.sources; do
    [ -r "$f" ] || continue
    uri=$(awk 'BEGIN { RS = ""; FS = "\n" }
        /(^|\n)Suites:[^\n]*[ \t]bookworm([ \t]|\n|$)/ && /(^|\n)Types:[^\n]*deb([ \t]|\n|$)/ {
            for (i = 1; i <= NF; i++) if ($i ~ /^URIs:/) { sub(/^URIs:[ \t]*/, "", $i);
                split($i, u, /[ \t]+/); print u[1]; exit } }' "$f")
    [ -n "$uri" ] && { echo "$uri"; exit 0; }
done
for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
    [ -r "$f" ] || continue
    uri=$(awk '$1 == "deb" { i = 2; if ($i ~ /^\[/) { while ($i !~ /\]$/) i++; i++ }
        if ($(i + 1) == "bookworm") { print $i; exit } }' "$f")
    [ -n "$uri" ] && { echo "$uri"; exit 0; }
done
echo "tools/debian_uri.sh: no Debian bookworm source in /etc/apt to take the URI from" >&2
exit 1
