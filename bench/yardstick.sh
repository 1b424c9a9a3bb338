#!/bin/sh
# bench/yardstick.sh - the library against the speed yardsticks of issues 15
# and 16 (2D, 3D), side by side in one run (make bench-yardstick;
# bench/README.md).
#
# Compiles the plain serial C kernels YARDSTICK_DIR/mpm2d.c and mpm3d.c and
# the driver YARDSTICK_DIR/libblock.c (the yardstick's scene through the
# public API: elastic block on a slip floor, linear shapes, USL, fixed dt,
# 2 points per cell per axis; its "2d" and "3d" cases, issues 15 and 16),
# the driver once per library given with --lib, all with the same compiler
# and flags. 2D: mpm2d.c against libblock 2d; 3D: mpm3d.c against libblock
# 3d. Then runs them interleaved: for every size and repetition, the
# yardstick and every (library, worker count) once each, the
# order rotated by one from one repetition to the next, so that a slow patch
# of a shared machine falls on all of them alike. Each program prints
# ns_per_point_step over its timed steps only (set-up excluded; the driver
# does 3 untimed warm-up steps). Reports medians, ratios library/yardstick,
# the speed-up of each worker count over 1 worker and, with several
# libraries, each library against the first.
#
# Writes RESULTS/DATE-TAG.csv (one row per run) and RESULTS/DATE-TAG.md (the
# machine, the flags and the medians). Nothing is written with --no-save.
#
# Usage: yardstick.sh [options]
#   --lib NAME=DIR     a library to measure; DIR is a build directory (with
#                      lib/.libs/libgranmpm.so), an install prefix (with
#                      lib/libgranmpm.so) or a directory holding
#                      libgranmpm.so. Repeat it to compare builds in one run
#                      (--lib before=../build-old --lib after=build).
#                      Default: this=<source tree>/build
#   --yardstick-dir D  where mpm2d.c and libblock.c are (default
#                      $YARDSTICK_DIR, else <source tree>/../shared/yardstick)
#   --quick            2D sizes 1e4 1e5 1e6, 3D sizes 1e5 1e6, 3
#                      repetitions, short runs (the default; 2D 64 s on
#                      the 2-core machine at load 6; 2D and 3D 47 s at
#                      load 2)
#   --full             2D sizes 1e4 1e5 1e6, 3D sizes 1e5 1e6, 7
#                      repetitions, runs 7.5x longer (2D about 11 min on the
#                      2-core machine at load 7-8; 3D several minutes more)
#   --dims "D ..."     which cases: 2, 3 or "2 3" (default "2 3")
#   --sizes "N ..."    2D points (a square block of round(sqrt(N/4)) cells
#                      per side; 1e4, 1e5, 1e6 give 10 000, 99 856,
#                      1 000 000)
#   --sizes-3d "N ..." 3D points (a cube of round(cbrt(N/8)) cells per side;
#                      1e5 and 1e6 give 97 336 and 1 000 000)
#   --reps R           repetitions
#   --workers "W ..."  worker counts of the library (default "1 2"; the
#                      first is the base of the speed-up)
#   --steps "N:S ..."  timed steps per size (default: a work budget per
#                      mode divided by the points, at least 5; a third of
#                      it in 3D, whose point-step costs about 3x 2D's);
#                      3D sizes are written 3d:N:S
#   --cc CC            compiler (default $CC, else cc)
#   --cflags "FLAGS"   flags of the yardstick and of the driver (default: the
#                      CFLAGS of the first --lib's build directory, as read
#                      from its Makefile, else -O3). The library keeps the
#                      flags it was built with (stated in the summary).
#   --results DIR      where the CSV and the summary go (default
#                      <source tree>/bench/results)
#   --tag TAG          file name after the date (default yardstick-MODE)
#   --no-save          print the summary only
set -eu

here=$(cd "$(dirname "$0")" && pwd)
srcdir=$(cd "$here/.." && pwd)

die() {
  echo "yardstick.sh: $*" >&2
  exit 2
}

libs=""
ysdir=${YARDSTICK_DIR:-$srcdir/../shared/yardstick}
mode=quick
sizes=""
sizes3=""
dims="2 3"
reps=""
workers="1 2"
steps_spec=""
cc=${CC:-cc}
cflags=""
cflags_set=no
results=$srcdir/bench/results
tag=""
save=yes
cmdline="bench/yardstick.sh"
for a in "$@"; do
  case $a in
  *[!A-Za-z0-9_./:=@+-]* | '') cmdline="$cmdline '$a'" ;;
  *) cmdline="$cmdline $a" ;;
  esac
done

while [ $# -gt 0 ]; do
  case $1 in
  --lib)
    [ $# -ge 2 ] || die "--lib needs NAME=DIR"
    case $2 in *=*) ;; *) die "--lib needs NAME=DIR, got '$2'" ;; esac
    libs="$libs
$2"
    shift 2
    ;;
  --yardstick-dir) ysdir=${2:?}; shift 2 ;;
  --quick) mode=quick; shift ;;
  --full) mode=full; shift ;;
  --sizes) sizes=${2:?}; shift 2 ;;
  --sizes-3d) sizes3=${2:?}; shift 2 ;;
  --dims) dims=${2:?}; shift 2 ;;
  --reps) reps=${2:?}; shift 2 ;;
  --workers) workers=${2:?}; shift 2 ;;
  --steps) steps_spec=${2:?}; shift 2 ;;
  --cc) cc=${2:?}; shift 2 ;;
  --cflags) cflags=${2?}; cflags_set=yes; shift 2 ;;
  --results) results=${2:?}; shift 2 ;;
  --tag) tag=${2:?}; shift 2 ;;
  --no-save) save=no; shift ;;
  -h | --help) sed -n '2,/^set -eu/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
  *) die "unknown option '$1' (--help lists them)" ;;
  esac
done

case $mode in
quick) budget=4000000; : "${reps:=3}"; : "${sizes3:=1e5 1e6}" ;;
full) budget=30000000; : "${reps:=7}"; : "${sizes3:=1e5 1e6}" ;;
esac
: "${sizes:=1e4 1e5 1e6}"
for dim in $dims; do
  case $dim in 2 | 3) ;; *) die "--dims takes 2 and 3, got '$dim'" ;; esac
done
: "${tag:=yardstick-$mode}"
[ -n "$libs" ] || libs="
this=$srcdir/build"

for f in mpm2d.c mpm3d.c libblock.c; do
  [ -f "$ysdir/$f" ] || die "the yardstick's $f is not in '$ysdir'.
  Give its directory: make bench-yardstick YARDSTICK_DIR=/path/to/yardstick
  (or configure YARDSTICK_DIR=..., or bench/yardstick.sh --yardstick-dir DIR)."
done
ysdir=$(cd "$ysdir" && pwd)
command -v "$cc" > /dev/null 2>&1 || die "compiler '$cc' not found"

# ------------------------------------------------------------- the libraries
# lib_dir DIR: the directory holding libgranmpm.so; lib_inc DIR: where
# granmpm.h is (a build directory's source tree, or PREFIX/include).
lib_dir() {
  for d in "$1/lib/.libs" "$1/.libs" "$1/lib" "$1/lib64" "$1"/lib/*-linux-gnu "$1"; do
    if [ -e "$d/libgranmpm.so" ]; then
      (cd "$d" && pwd)
      return 0
    fi
  done
  return 1
}
build_srcdir() { # the source tree of a build directory (empty for a prefix)
  [ -f "$1/Makefile" ] && sed -n 's/^abs_top_srcdir = //p' "$1/Makefile" | head -n 1
}
lib_inc() {
  s=$(build_srcdir "$1" || true)
  if [ -n "$s" ] && [ -f "$s/include/granmpm.h" ]; then
    echo "$s/include"
  elif [ -f "$1/include/granmpm.h" ]; then
    (cd "$1/include" && pwd)
  else
    return 1
  fi
}
lib_cflags() { # the CFLAGS a build directory was configured with
  [ -f "$1/Makefile" ] && sed -n 's/^CFLAGS = //p' "$1/Makefile" | head -n 1
}
lib_commit() {
  s=$(build_srcdir "$1" || true)
  if [ -n "$s" ] && git -C "$s" rev-parse --short HEAD > /dev/null 2>&1; then
    c=$(git -C "$s" rev-parse --short HEAD)
    if [ -n "$(git -C "$s" status --porcelain --untracked-files=no 2> /dev/null)" ]; then
      c="$c+uncommitted changes"
    fi
    echo "$c"
  else
    echo "unknown (not a build directory of a git checkout)"
  fi
}

work=$(mktemp -d "${TMPDIR:-/tmp}/yardstick.XXXXXX")
trap 'rm -rf "$work"' EXIT INT TERM

names=""
first_lib=""
libinfo=""
for spec in $libs; do
  name=${spec%%=*}
  path=${spec#*=}
  case $name in '' | *[!A-Za-z0-9_.-]*) die "library name '$name': use letters, digits, . _ -" ;; esac
  case " $names " in *" $name "*) die "library name '$name' given twice" ;; esac
  [ -d "$path" ] || die "--lib $name: '$path' is not a directory"
  path=$(cd "$path" && pwd)
  ldir=$(lib_dir "$path") || die "--lib $name: no libgranmpm.so under '$path' (build it first: make -C $path lib/libgranmpm.la)"
  inc=$(lib_inc "$path") || die "--lib $name: granmpm.h not found for '$path'"
  [ -n "$first_lib" ] || first_lib=$path
  names="$names $name"
  echo "$ldir" > "$work/$name.libdir"
  lflags=$(lib_cflags "$path" || true)
  libinfo="$libinfo
  - \`$name\` = \`$path\`: \`$ldir/libgranmpm.so\`, commit $(lib_commit "$path"), library built with CFLAGS \`${lflags:-unknown (not a build directory)}\`"
done
names=${names# }

if [ $cflags_set = no ]; then
  cflags=$(lib_cflags "$first_lib" || true)
  : "${cflags:=-O3}"
fi

# ---------------------------------------------------------------- compiling
echo "compiling with $cc $cflags" >&2
# shellcheck disable=SC2086 # cflags is a list of flags
"$cc" $cflags -o "$work/mpm2d" "$ysdir/mpm2d.c" -lm ||
  die "compiling $ysdir/mpm2d.c failed"
# shellcheck disable=SC2086
"$cc" $cflags -o "$work/mpm3d" "$ysdir/mpm3d.c" -lm ||
  die "compiling $ysdir/mpm3d.c failed"
for name in $names; do
  ldir=$(cat "$work/$name.libdir")
  path=$(echo "$libs" | sed -n "s/^$name=//p")
  inc=$(lib_inc "$path")
  # shellcheck disable=SC2086
  "$cc" $cflags -I"$inc" -o "$work/libblock-$name" "$ysdir/libblock.c" \
    -L"$ldir" -Wl,-rpath,"$ldir" -lgranmpm -lm ||
    die "compiling $ysdir/libblock.c against $ldir failed"
  # The driver must load this library, not an installed one.
  got=$(LD_LIBRARY_PATH=$ldir ldd "$work/libblock-$name" | sed -n 's/^[[:space:]]*libgranmpm[^ ]* => \([^ ]*\).*/\1/p')
  case $got in
  "$ldir"/*) ;;
  *) die "libblock-$name loads '$got', not the library in $ldir" ;;
  esac
done

# ------------------------------------------------------------------ running
# side_of DIM N: cells per side of the square block (4 points a cell) or
# of the cube (8 points a cell); points_of DIM SIDE: its points.
side_of() {
  awk -v d="$1" -v n="$2" 'BEGIN {
    s = (d == 3) ? int(exp(log(n / 8) / 3) + 0.5) : int(sqrt(n / 4) + 0.5)
    if (s < 1) s = 1; print s }'
}
points_of() {
  if [ "$1" = 3 ]; then echo $((8 * $2 * $2 * $2)); else echo $((4 * $2 * $2)); fi
}
steps_of() { # DIM SIZE POINTS
  s=""
  for kv in $steps_spec; do
    case $1:$kv in
    3:3d:*:*) [ "$(echo "$kv" | cut -d: -f2)" = "$2" ] && s=${kv##*:} ;;
    2:3d:*) ;;
    2:*) [ "${kv%%:*}" = "$2" ] && s=${kv#*:} ;;
    esac
  done
  b=$budget
  [ "$1" = 3 ] && b=$((budget / 3))
  [ -n "$s" ] || s=$(awk -v n="$3" -v b="$b" 'BEGIN { s = int(b / n + 0.5); if (s < 5) s = 5; print s }')
  echo "$s"
}
sizes_of() { if [ "$1" = 3 ]; then echo "$sizes3"; else echo "$sizes"; fi; }

day=$(date +%Y-%m-%d)
base=$results/$day-$tag
if [ $save = yes ]; then
  mkdir -p "$results"
  i=2
  while [ -e "$base.csv" ] || [ -e "$base.md" ]; do
    base=$results/$day-$tag-$i
    i=$((i + 1))
  done
fi
csv=$work/runs.csv
echo "size,points,steps,rep,slot,program,library,workers,load1,seconds,ns_per_point_step,dim" > "$csv"

load_start=$(cut -d' ' -f1-3 /proc/loadavg 2> /dev/null || echo unknown)
t_start=$(date +%s)
echo "load average at start: $load_start" >&2

# The runs of one repetition: "yardstick" then library:workers pairs.
slots="yardstick"
for name in $names; do
  for w in $workers; do slots="$slots $name:$w"; done
done
nslots=$(echo "$slots" | wc -w)

for dim in $dims; do
for size in $(sizes_of "$dim"); do
  side=$(side_of "$dim" "$size")
  points=$(points_of "$dim" "$side")
  steps=$(steps_of "$dim" "$size" "$points")
  rep=1
  while [ "$rep" -le "$reps" ]; do
    # Rotate the order by one each repetition.
    k=0
    while [ $k -lt "$nslots" ]; do
      idx=$(((k + rep - 1) % nslots + 1))
      slot=$(echo "$slots" | cut -d' ' -f"$idx")
      load1=$(cut -d' ' -f1 /proc/loadavg 2> /dev/null || echo nan)
      cube="$side $side"
      [ "$dim" = 3 ] && cube="$side $side $side"
      if [ "$slot" = yardstick ]; then
        # shellcheck disable=SC2086 # cube is the block's cells per axis
        out=$("$work/mpm${dim}d" $cube "$steps") || die "mpm${dim}d $cube $steps failed"
        lib=""
        w=1
      else
        lib=${slot%%:*}
        w=${slot#*:}
        # shellcheck disable=SC2086
        out=$(LD_LIBRARY_PATH=$(cat "$work/$lib.libdir") "$work/libblock-$lib" "${dim}d" $cube "$steps" "$w") ||
          die "libblock ($lib) ${dim}d $cube $steps $w failed: $out"
      fi
      got_points=$(echo "$out" | sed -n 's/.*points=\([0-9]*\).*/\1/p')
      secs=$(echo "$out" | sed -n 's/.*seconds=\([0-9.]*\).*/\1/p')
      ns=$(echo "$out" | sed -n 's/.*ns_per_point_step=\([0-9.]*\).*/\1/p')
      [ -n "$ns" ] || die "no ns_per_point_step in: $out"
      [ "$got_points" = "$points" ] || die "$slot ran $got_points points, expected $points"
      prog=library
      [ "$slot" = yardstick ] && prog=yardstick
      echo "$size,$points,$steps,$rep,$((k + 1)),$prog,$lib,$w,$load1,$secs,$ns,$dim" >> "$csv"
      printf '%sD %s %s rep %s: %-14s %8s ns/point-step (load %s)\n' "$dim" "$size" "$points" "$rep" "$slot" "$ns" "$load1" >&2
      k=$((k + 1))
    done
    rep=$((rep + 1))
  done
done
done
load_end=$(cut -d' ' -f1-3 /proc/loadavg 2> /dev/null || echo unknown)
elapsed=$(($(date +%s) - t_start))

# ------------------------------------------------------------------ summary
# median FILTER: the median (and min, max) of ns_per_point_step over the
# rows of the CSV whose size, program, library and workers match.
stats() { # size program library workers -> "median min max" (of dim $dim)
  awk -F, -v s="$1" -v p="$2" -v l="$3" -v w="$4" -v d="$dim" \
    'NR > 1 && $1 == s && $6 == p && $7 == l && $8 == w && $12 == d { print $11 }' "$csv" |
    sort -g | awk '{ v[NR] = $1 } END {
      if (NR == 0) { print "nan nan nan"; exit }
      m = (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2
      print m, v[1], v[NR] }'
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", a / b }'; }
fmt() { awk -v m="$1" -v lo="$2" -v hi="$3" 'BEGIN { printf "%.1f (%.1f–%.1f)", m, lo, hi }'; }

cpu=$(lscpu 2> /dev/null | sed -n 's/^Model name:[[:space:]]*//p' | head -n 1)
ncpu=$(nproc 2> /dev/null || echo "?")
caches=$(lscpu 2> /dev/null | sed -n 's/^\(L[23]\) cache:[[:space:]]*/\1 /p' | tr '\n' ';' | sed 's/;$//; s/;/, /g')
virt=$(lscpu 2> /dev/null | sed -n 's/^Hypervisor vendor:[[:space:]]*//p')
mem=$(awk '/^MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo 2> /dev/null || echo "?")
ccver=$("$cc" --version 2> /dev/null | head -n 1)
wbase=$(echo "$workers" | cut -d' ' -f1)
lib1=$(echo "$names" | cut -d' ' -f1)

{
  echo "# Library against the yardstick, $day ($mode mode)"
  echo
  echo "Command: \`$cmdline\`"
  echo "($reps interleaved repetitions, the order rotated each repetition; ${elapsed} s)."
  echo "Raw runs: \`$(basename "$base").csv\`."
  echo
  echo "## Machine and build"
  echo
  echo "- CPU: ${cpu:-unknown}, $ncpu logical CPUs${virt:+, virtual machine ($virt)}; ${caches:-caches unknown}; $mem RAM; $(uname -sr)."
  echo "- Load average (1, 5, 15 min) at start: $load_start; at end: $load_end. Each run's 1-minute load is in the CSV."
  echo "- A shared machine: other jobs ran during the measurement, so absolute times"
  echo "  vary between runs; the ratios are more stable because the runs are interleaved."
  echo "- Compiler: $ccver. Yardsticks (\`$ysdir/mpm2d.c\`, \`mpm3d.c\`) and driver"
  echo "  (\`$ysdir/libblock.c\`) compiled with \`$cflags\`."
  echo "- Libraries:$libinfo"
  echo "- Scene (both programs): elastic block (E = 1e7 Pa, nu = 0.3, rho = 1800 kg/m^3) on a slip"
  echo "  floor under gravity, h = 0.01 m, 2 points per cell per axis (2D: a square block, 3D: a"
  echo "  cube), linear shapes, USL, dt = 0.5 h / c."
  echo
  for dim in $dims; do
  dim_sizes=$(sizes_of "$dim")
    echo "## ${dim}D: medians (min–max) in ns per point-step"
    echo
    echo "Yardstick \`mpm${dim}d.c\`, library \`libblock ${dim}d\`."
    echo
    hdr="| points | steps | yardstick |"
    sep="| ---: | ---: | ---: |"
    for name in $names; do
      for w in $workers; do
        hdr="$hdr $name, $w w | ratio to yardstick |"
        sep="$sep ---: | ---: |"
      done
    done
    echo "$hdr"
    echo "$sep"
    for size in $dim_sizes; do
      side=$(side_of "$dim" "$size")
      points=$(points_of "$dim" "$side")
      steps=$(steps_of "$dim" "$size" "$points")
      # shellcheck disable=SC2046
      set -- $(stats "$size" yardstick "" 1)
      ys=$1
      row="| $points | $steps | $(fmt "$1" "$2" "$3") |"
      for name in $names; do
        for w in $workers; do
          # shellcheck disable=SC2046
          set -- $(stats "$size" library "$name" "$w")
          row="$row $(fmt "$1" "$2" "$3") | $(ratio "$1" "$ys") |"
        done
      done
      echo "$row"
    done
    echo
    echo "${dim}D speed-up over $wbase worker (median ns at $wbase worker / median ns at W workers):"
    echo
    for name in $names; do
      for size in $dim_sizes; do
        line="- $name, $size points:"
        # shellcheck disable=SC2046
        set -- $(stats "$size" library "$name" "$wbase")
        b=$1
        for w in $workers; do
          [ "$w" = "$wbase" ] && continue
          # shellcheck disable=SC2046
          set -- $(stats "$size" library "$name" "$w")
          line="$line $w workers $(ratio "$b" "$1")x"
        done
        echo "$line"
      done
    done
    smallest=$(echo "$dim_sizes" | cut -d' ' -f1)
    largest=$(echo "$dim_sizes" | awk '{ print $NF }')
    if [ "$smallest" != "$largest" ]; then
      echo
      echo "${dim}D per-point cost at $largest over $smallest points (medians, $wbase worker):"
      echo
      # shellcheck disable=SC2046
      set -- $(stats "$largest" yardstick "" 1)
      yl=$1
      # shellcheck disable=SC2046
      set -- $(stats "$smallest" yardstick "" 1)
      echo "- yardstick: $(ratio "$yl" "$1")"
      for name in $names; do
        # shellcheck disable=SC2046
        set -- $(stats "$largest" library "$name" "$wbase")
        ll=$1
        # shellcheck disable=SC2046
        set -- $(stats "$smallest" library "$name" "$wbase")
        echo "- $name: $(ratio "$ll" "$1")"
      done
    fi
    if [ "$names" != "$lib1" ]; then
      echo
      echo "${dim}D: each library against \`$lib1\` (median ns / median ns of \`$lib1\`, same workers; below 1 is faster):"
      echo
      for name in $names; do
        [ "$name" = "$lib1" ] && continue
        for size in $dim_sizes; do
          line="- $name, $size points:"
          for w in $workers; do
            # shellcheck disable=SC2046
            set -- $(stats "$size" library "$lib1" "$w")
            a=$1
            # shellcheck disable=SC2046
            set -- $(stats "$size" library "$name" "$w")
            line="$line $w w $(ratio "$1" "$a");"
          done
          echo "${line%;}"
        done
      done
    fi
  echo
  done
} > "$work/summary.md"

cat "$work/summary.md"
if [ $save = yes ]; then
  cp "$csv" "$base.csv"
  cp "$work/summary.md" "$base.md"
  echo "wrote $base.csv and $base.md" >&2
fi
