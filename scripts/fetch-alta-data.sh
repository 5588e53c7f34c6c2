#!/usr/bin/env bash
# Fetches ALTA's retro-reflection measurements (three retro-reflective tapes measured at
# CEA-CESTA, https://hal.inria.fr/hal-01083366/) from ALTA's repository,
# https://github.com/mkae/alta, folder documents/data, into DIR and checks their hashes.
# The files are not part of this repository: ALTA is under MPL-2.0 and its authors ask to be
# contacted before reuse (docs/model.md, "ALTA"). Needs network access; not run in CI.
#
# Usage: scripts/fetch-alta-data.sh [--git] DIR
#   DIR    folder to write the .dat files to (created if missing)
#   --git  fetch with a sparse, blob-less git clone of documents/data instead of curl
# Then: BRDF_SLS_ALTA_DATA=DIR cargo test -p brdf-io --test alta_data
#
# Files are taken at ALTA commit $COMMIT (the data last changed in 2015). Each is checked by
# its git blob id and, where known, its SHA-256; retro-orange-tape.dat was missing from the
# snapshot the SHA-256 list was made from, so only its blob id is checked (its SHA-256 is
# printed). Exits non-zero when a download fails or a hash differs.
set -euo pipefail

COMMIT=63aa68404b490d9fbacb6578080689e1597227c7
REPO=https://github.com/mkae/alta
RAW=https://raw.githubusercontent.com/mkae/alta/$COMMIT/documents/data

# name, size in bytes ("-": not known), SHA-256 ("-": not known), git blob id.
FILES=(
    "retro-3M-jaune.dat 1066493 8a40ee3592129dfeb8c5fe0f05b8ec647e52ded4c4fb762c9b821c90ffd9be76 ddc2f877c826474e11d94020875ed21370f33d71"
    "retro-3M-jaune-dense.dat 3291559 898a47a0737366a845ad7275ced471560308f53df0cc623424ab0063bd9b1482 95b0fa7bbb749a6f146ba05a40fd070b3c069009"
    "retro-gray-tape.dat 1067628 32a755fd490a5de84acba86f5673ecbf0972fa14584c8f23dd61aa6d4009d508 dbdd3d24507c0224d5810f83b9c54da669d02cf5"
    "retro-gray-tape-dense.dat 3787028 7b596e46fa4facdb360edab1bc68e15110db344183c0a295612636b5af36a0f4 e6ddb8b36ce8d5ce43e6608d9b46d2ac072480a3"
    "retro-orange-tape-dense.dat 3786633 8fdbd15e8063904f5944e75fe24dce8021c0f95380d292b2d99c9e7e297576fa 99ca67324b440665690488ed0fe99af4fea89b44"
    "retro-orange-tape.dat - - e02d7a1cf2df076dd2d52f837cdb35d9e1b6f15a"
)

usage() {
    sed -n '8,11p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
}

use_git=0
dir=
for arg in "$@"; do
    case $arg in
        --git) use_git=1 ;;
        -h | --help) usage ;;
        -*) echo "fetch-alta-data: unknown option $arg" >&2; usage ;;
        *)
            [ -z "$dir" ] || usage
            dir=$arg
            ;;
    esac
done
[ -n "$dir" ] || usage

sha256() {
    if command -v sha256sum >/dev/null; then
        sha256sum "$1" | cut -d' ' -f1
    else
        shasum -a 256 "$1" | cut -d' ' -f1
    fi
}

sha1() {
    if command -v sha1sum >/dev/null; then
        sha1sum | cut -d' ' -f1
    else
        shasum -a 1 | cut -d' ' -f1
    fi
}

# The git blob id of a file: SHA-1 of "blob SIZE\0" followed by the content.
blob_id() {
    local size
    size=$(wc -c <"$1" | tr -d ' ')
    { printf 'blob %s\0' "$size"; cat "$1"; } | sha1
}

mkdir -p "$dir"

if [ "$use_git" -eq 1 ]; then
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    git clone --quiet --filter=blob:none --sparse "$REPO" "$tmp/alta"
    git -C "$tmp/alta" sparse-checkout set documents/data
    git -C "$tmp/alta" checkout --quiet "$COMMIT"
    for entry in "${FILES[@]}"; do
        read -r name _ <<<"$entry"
        cp "$tmp/alta/documents/data/$name" "$dir/$name"
    done
else
    for entry in "${FILES[@]}"; do
        read -r name _ <<<"$entry"
        echo "fetching $name"
        curl -fsSL --retry 3 -o "$dir/$name.part" "$RAW/$name"
        mv "$dir/$name.part" "$dir/$name"
    done
fi

status=0
for entry in "${FILES[@]}"; do
    read -r name size sum blob <<<"$entry"
    file=$dir/$name
    got_blob=$(blob_id "$file")
    got_sum=$(sha256 "$file")
    got_size=$(wc -c <"$file" | tr -d ' ')
    if [ "$got_blob" != "$blob" ]; then
        echo "BAD  $name: git blob $got_blob, expected $blob" >&2
        status=1
    elif [ "$sum" != "-" ] && { [ "$got_sum" != "$sum" ] || [ "$got_size" != "$size" ]; }; then
        echo "BAD  $name: $got_size bytes, SHA-256 $got_sum; expected $size bytes, $sum" >&2
        status=1
    elif [ "$sum" = "-" ]; then
        echo "ok   $name ($got_size bytes, git blob matches; SHA-256 $got_sum)"
    else
        echo "ok   $name ($got_size bytes, SHA-256 matches)"
    fi
done
if [ "$status" -ne 0 ]; then
    echo "fetch-alta-data: hashes differ; the files were kept in $dir for inspection" >&2
    exit "$status"
fi
echo "done: BRDF_SLS_ALTA_DATA=$dir cargo test -p brdf-io --test alta_data"
