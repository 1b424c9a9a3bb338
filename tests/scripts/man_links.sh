#!/bin/sh
# tests/scripts/man_links.sh - every exported gm_* function has a manual page
# (`man gm_X` works: its own page or a .so stub to its group page), and the
# stubs in man/links are what man/make-links.sh writes from the group pages'
# NAME sections (a function added to a page without re-running the script
# fails here). The exported symbols are read from the built library, so a
# new API function without documentation fails too.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
srcdir=${srcdir:-.}
lib=lib/.libs/libgranmpm.so
if [ ! -f "$lib" ]; then
  echo "SKIP: $lib not built (shared library disabled)"
  exit 77
fi
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
sh "$srcdir/man/make-links.sh" "$srcdir" "$scratch"
failed=0
for stub in "$scratch"/*.3 "$scratch"/links.mk; do
  name=$(basename "$stub")
  if ! cmp -s "$stub" "$srcdir/man/links/$name"; then
    echo "FAIL: man/links/$name is not current: run man/make-links.sh"
    failed=1
  fi
done
for stub in "$srcdir"/man/links/*.3; do
  if [ ! -f "$scratch/$(basename "$stub")" ]; then
    echo "FAIL: man/links/$(basename "$stub") names no function of a page"
    failed=1
  fi
done
symbols=$(nm -D --defined-only "$lib" | awk '{ print $3 }' |
  sed 's/@.*//' | grep '^gm_' | sort -u)
count=0
for symbol in $symbols; do
  count=$((count + 1))
  if [ ! -f "$srcdir/man/$symbol.3" ] &&
    [ ! -f "$srcdir/man/links/$symbol.3" ]; then
    echo "FAIL: exported $symbol has no manual page"
    failed=1
  fi
done
echo "$count exported functions checked against the manual pages"
exit $failed
