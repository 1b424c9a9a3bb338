#!/bin/sh
# fuzz/run.sh BUILD SECONDS - runs each libFuzzer harness built in BUILD
# (configure --enable-fuzz) for SECONDS, starting from the seed corpus
# (fuzz/corpus/<harness>, plus a generated checkpoint), growing a working
# corpus in BUILD/fuzz-corpus/<harness>. A crash, a sanitizer report or a
# broken promise stops that harness and fails the run; the input that did
# it is kept as BUILD/fuzz-artifacts/<harness>-crash-*: reproduce with
# BUILD/fuzz/<harness> <that file>.
# SPDX-License-Identifier: BSD-2-Clause
set -eu
build=$1
seconds=$2
srcdir=$(cd "$(dirname "$0")/.." && pwd)
failed=0
for harness in fuzz_api fuzz_checkpoint; do
  corpus=$build/fuzz-corpus/$harness
  artifacts=$build/fuzz-artifacts
  mkdir -p "$corpus" "$artifacts"
  if [ -d "$srcdir/fuzz/corpus/$harness" ]; then
    cp "$srcdir/fuzz/corpus/$harness"/* "$corpus"/
  fi
  if [ "$harness" = fuzz_checkpoint ]; then
    GM_FUZZ_WRITE_SEED=$corpus/seed.ckpt "$build/fuzz/$harness" # and seed.ckpt.3d
  fi
  echo "=== $harness for $seconds s"
  # -timeout: one input over 10 s is a hang; -rss_limit_mb: a leak or an
  # allocation the harness failed to bound.
  if ! ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 \
    UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/fuzz/$harness" -max_total_time="$seconds" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$artifacts/$harness-" "$corpus"; then
    echo "FAILED: $harness (the input is in $artifacts)"
    failed=1
  fi
done
exit $failed
