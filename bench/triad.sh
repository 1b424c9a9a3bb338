#!/bin/sh
# bench/triad.sh - the machine's triad bandwidth (bench/triad.c), recorded
# with the machine and its load (make bench-triad, also run first by make
# bench-yardstick; bench/README.md). The memory bound of the step in
# docs/performance.md is bytes per point-step over this bandwidth.
#
# Usage: triad.sh PROGRAM RESULTS_DIR [triad options]
#   PROGRAM      the built granmpm-triad
#   RESULTS_DIR  where DATE-triad.{csv,md} go ("-": print only)
#   options      passed to the program (--mib, --reps, --threads)
set -eu

[ $# -ge 2 ] || {
  echo "usage: triad.sh PROGRAM RESULTS_DIR [options]" >&2
  exit 2
}
program=$1
results=$2
shift 2
[ -x "$program" ] || {
  echo "triad.sh: $program is not an executable" >&2
  exit 2
}

load() { cut -d' ' -f1-3 /proc/loadavg 2> /dev/null || echo "?"; }
load_start=$(load)
csv=$("$program" "$@")
load_end=$(load)
echo "$csv"

[ "$results" != "-" ] || exit 0
day=$(date -u +%Y-%m-%d)
base=$results/$day-triad
mkdir -p "$results"
echo "$csv" > "$base.csv"
cpu=$(lscpu 2> /dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1)
caches=$(lscpu 2> /dev/null | sed -n 's/^\(L[23]\) cache:[[:space:]]*/\1 /p' | tr '\n' ';' | sed 's/;$//; s/;/, /g')
{
  echo "# Triad bandwidth, $day"
  echo
  echo "Command: \`bench/triad.sh $program $results $*\` ($(date -u +%H:%M) UTC)."
  echo "Raw rows: \`$(basename "$base").csv\`."
  echo
  echo "- CPU: ${cpu:-unknown}, $(nproc 2> /dev/null || echo '?') logical CPUs; ${caches:-caches unknown}; $(uname -sr)."
  echo "- Load average (1, 5, 15 min) at start: $load_start; at end: $load_end."
  echo "- a[i] = b[i] + 3 c[i]; GB/s = 24 bytes per element / best time (STREAM"
  echo "  convention; the bus also carries the write-allocate read, 32 bytes)."
  echo
  echo "| threads | MiB per array | repetitions | best GB/s | median GB/s |"
  echo "| ---: | ---: | ---: | ---: | ---: |"
  echo "$csv" | awk -F, 'NR > 1 { printf "| %s | %s | %s | %s | %s |\n", $1, $2, $3, $5, $6 }'
} > "$base.md"
echo "triad.sh: wrote $base.csv and $base.md" >&2
