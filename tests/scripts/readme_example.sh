#!/bin/sh
# tests/scripts/readme_example.sh - the README's minimal program and the EXAMPLE of
# granmpm(3) are examples/minimal.c, which make check builds and runs: the
# program a user copies is one that compiles and works. Fails when the
# three copies differ.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
srcdir=${srcdir:-.}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
awk '/^```c$/ { on = 1; next } /^```$/ { if (on) exit } on' \
  "$srcdir/README.md" >"$scratch/readme.c"
# The first .EX block after .SH EXAMPLE, with the roff escapes undone.
awk '/^\.SH EXAMPLE/ { section = 1 } section && /^\.EX/ { on = 1; next }
  on && /^\.EE/ { exit } on' "$srcdir/man/granmpm.3" |
  sed 's/\\-/-/g; s/\\e/\\/g' >"$scratch/man.c"
failed=0
for copy in readme man; do
  if ! diff -u "$srcdir/examples/minimal.c" "$scratch/$copy.c"; then
    echo "FAIL: the $copy copy of the minimal program differs from examples/minimal.c"
    failed=1
  fi
done
exit $failed
