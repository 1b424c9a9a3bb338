#!/bin/sh
# tests/scripts/stable_api.sh - the stable/provisional split of granmpm.h holds:
#  1. the README's minimal program compiles with GM_STABLE_ONLY (it uses the
#     stable API only, the one a user is told to start from);
#  2. with GM_STABLE_ONLY a call to a provisional function does not compile
#     (the guard hides the provisional section), without it it does;
#  3. granmpm(3) STABILITY names every function of the provisional section.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
srcdir=${srcdir:-.}
cc=${CC:-cc}
header="$srcdir/include/granmpm.h"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
flags="-std=c11 -Wall -Wextra -Wpedantic -Werror -fsyntax-only -I$srcdir/include"
failed=0

if ! $cc $flags -DGM_STABLE_ONLY "$srcdir/examples/minimal.c"; then
  echo "FAIL: examples/minimal.c needs the provisional API"
  failed=1
fi

cat >"$scratch/provisional.c" <<'PROGRAM'
#include <granmpm.h>
int uses_a_view(const gm_domain *domain) {
  const double *x = 0;
  return (int)gm_domain_view_field(domain, GM_FIELD_POSITION, 0, &x);
}
PROGRAM
if ! $cc $flags "$scratch/provisional.c"; then
  echo "FAIL: a provisional call does not compile in the default mode"
  failed=1
fi
if $cc $flags -DGM_STABLE_ONLY "$scratch/provisional.c" 2>/dev/null; then
  echo "FAIL: GM_STABLE_ONLY does not hide gm_domain_view_field"
  failed=1
fi

# The provisional functions: declared after the PROVISIONAL banner, and in
# the headers included there.
sed -n '/^\/\* =* PROVISIONAL/,/GM_STABLE_ONLY \*\//p' "$header" >"$scratch/part.h"
for included in $(sed -n 's/^#include "\(granmpm\/.*\.h\)"$/\1/p' "$scratch/part.h"); do
  cat "$srcdir/include/$included" >>"$scratch/part.h"
done
names=$(tr '\n' ' ' <"$scratch/part.h" |
  grep -o 'GM_API [a-z_ ]*[ *]gm_[a-z0-9_]*(' | sed 's/.*\(gm_[a-z0-9_]*\)(/\1/')
if [ -z "$names" ]; then
  echo "FAIL: no provisional function found in $header"
  failed=1
fi
awk '/^\.SH STABILITY/ { on = 1; next } /^\.SH / { on = 0 } on' \
  "$srcdir/man/granmpm.3" >"$scratch/stability"
for name in $names; do
  if ! grep -q "$name" "$scratch/stability"; then
    echo "FAIL: granmpm(3) STABILITY does not name provisional $name"
    failed=1
  fi
done
exit $failed
