#!/bin/sh
# tests/scripts/layering.sh - the folders of lib/ stay layered (docs/architecture.md,
# "Folders and layers"). Fails when
#  - a source or header sits outside the known folders (or directly in lib/);
#  - a file includes a header of a folder above its own layer, or a header
#    of another folder other than that folder's own header (X/X.h) or one
#    of the few others it exports (EXPORTED below): the other headers of a
#    folder are private to it;
#  - a .c file's first library include is not its own folder's header;
#  - the include graph between folders has a cycle (tsort);
#  - when the library's objects are built (the build directory, where make
#    check runs): an object calls a gm_ function defined in a folder above
#    its own (a prototype written by hand would pass the include rules).
# The order below is the one place the layers are written down; the
# architecture document shows the same order.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
srcdir=${srcdir:-.}
LAYERS="shapes core points materials boundaries granular grid step io"
# Headers besides X/X.h that other folders may include: core/ exports the
# small core (core.h) and, apart, the domain's data layout (domain.h).
EXPORTED="core/domain.h"

scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
rank=0
for layer in $LAYERS; do
  echo "$layer $rank" >> "$scratch/ranks"
  rank=$((rank + 1))
done

failed=0
cd "$srcdir/lib"
for file in *.c *.h */*.c */*.h */*/*.c */*/*.h; do
  [ -f "$file" ] || continue
  case $file in
  */*/*)
    echo "FAIL: lib/$file: folders are one level deep"
    failed=1
    continue
    ;;
  */*) ;;
  *)
    echo "FAIL: lib/$file: a source directly in lib/ (put it in a folder)"
    failed=1
    continue
    ;;
  esac
  folder=${file%%/*}
  # One line per quoted include: file, its folder, line number, header.
  awk -v file="$file" -v folder="$folder" '
    /^[ \t]*#[ \t]*include[ \t]*"/ {
      header = $0
      sub(/^[^"]*"/, "", header)
      sub(/".*$/, "", header)
      print file, folder, FNR, header
    }' "$file"
done > "$scratch/includes"

# Every rule on the includes, in one awk over the rank table.
awk -v scratch="$scratch" -v exported="$EXPORTED" '
  BEGIN { n = split(exported, list, " "); for (k = 1; k <= n; k++) open[list[k]] = 1 }
  NR == FNR { rank[$1] = $2; next }
  {
    file = $1; folder = $2; line = $3; header = $4
    where = "lib/" file ":" line
    if (!(folder in rank)) {
      printf "FAIL: lib/%s: folder %s is not in the layers\n", file, folder
      bad = 1
      next
    }
    public = header == "granmpm.h" || header ~ /^granmpm\//
    if (file ~ /\.c$/ && !public && !(file in first)) {
      first[file] = 1
      if (header != folder "/" folder ".h") {
        printf "FAIL: %s: the first library include of a .c is its folder " \
               "header %s/%s.h, not %s\n", where, folder, folder, header
        bad = 1
      }
    }
    if (public)
      next
    if (header !~ /\//) {
      printf "FAIL: %s: include \"%s\" without its folder " \
             "(write \"%s/%s\")\n", where, header, folder, header
      bad = 1
      next
    }
    target = header
    sub(/\/.*$/, "", target)
    if (!(target in rank)) {
      printf "FAIL: %s: \"%s\" is not in a known folder\n", where, header
      bad = 1
      next
    }
    if (target == folder)
      next
    print folder, target >> (scratch "/edges")
    if (rank[target] > rank[folder]) {
      printf "FAIL: %s: %s/ includes \"%s\" of %s/, a layer above it\n",
             where, folder, header, target
      bad = 1
    }
    if (header != target "/" target ".h" && !(header in open)) {
      also = target == "core" ? " or core/domain.h" : ""
      printf "FAIL: %s: \"%s\" is private to %s/: include %s/%s.h%s\n",
             where, header, target, target, target, also
      bad = 1
    }
  }
  END { exit bad }' "$scratch/ranks" "$scratch/includes" || failed=1

# Cycles between folders, whatever the ranks say.
if [ -s "$scratch/edges" ]; then
  sort -u "$scratch/edges" > "$scratch/edges.sorted"
  if ! tsort "$scratch/edges.sorted" > /dev/null 2> "$scratch/tsort"; then
    echo "FAIL: the folders include each other in a cycle:"
    sed 's/^/  /' "$scratch/tsort"
    failed=1
  fi
fi
cd - > /dev/null

# Calls between the built objects (skipped where nm or the objects are not
# there, e.g. when run by hand from the source tree).
objects=$(for layer in $LAYERS; do
  [ -d "lib/$layer" ] && find "lib/$layer" -name '*.o' ! -path '*/.libs/*'
done 2> /dev/null | sort)
if command -v nm > /dev/null 2>&1 && [ -n "$objects" ]; then
  for object in $objects; do
    folder=${object#lib/}
    folder=${folder%%/*}
    nm "$object" | awk -v folder="$folder" -v object="$object" '
      $1 == "U" && $2 ~ /^gm_/ { print "use", folder, $2, object }
      NF == 3 && $2 ~ /^[TDBR]$/ && $3 ~ /^gm_/ { print "def", folder, $3, object }'
  done > "$scratch/symbols"
  awk 'NR == FNR { rank[$1] = $2; next }
    $1 == "def" { home[$3] = $2; next }
    $1 == "use" { use[++n] = $0 }
    END {
      for (k = 1; k <= n; k++) {
        split(use[k], u, " ")
        if ((u[3] in home) && rank[home[u[3]]] > rank[u[2]]) {
          printf "FAIL: %s (%s/) calls %s of %s/, a layer above it\n",
                 u[4], u[2], u[3], home[u[3]]
          bad = 1
        }
      }
      exit bad
    }' "$scratch/ranks" "$scratch/symbols" || failed=1
fi

if [ "$failed" -eq 0 ]; then
  echo "PASS: lib/ layers $LAYERS"
fi
exit "$failed"
