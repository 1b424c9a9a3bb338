# tests/scripts/slow_case.sh - sourced (`. "$(dirname "$0")/slow_case.sh"`)
# by the script tests that run a sweep of example runs: a slow case
# (tests/README.md, "Slow cases"), so it exits 77 (Automake's skip) when
# CK_EXCLUDE_TAGS names the tag slow, as the CI's sanitize and distcheck
# stages set it; otherwise it makes $scratch, a temporary directory removed
# when the test exits.
# SPDX-License-Identifier: BSD-2-Clause
case " ${CK_EXCLUDE_TAGS:-} " in
*" slow "*)
  echo "SKIP: a slow case and CK_EXCLUDE_TAGS='$CK_EXCLUDE_TAGS'"
  exit 77
  ;;
esac
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
