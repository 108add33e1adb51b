#!/usr/bin/env bash
# scripts/algray.sh checks its argument before it installs or builds anything: a typo
# ("rendr") ran apt-get for some 20 packages and only then printed the usage line.
# Every command the script installs or builds with is a stub first on PATH that records
# its call and fails, so this test can never install a package or start a build.
# Usage: algray_sh_usage_test.sh SOURCE_DIR
set -u
root=$1
stubs=$(mktemp -d)
trap 'rm -rf "$stubs"' EXIT
for cmd in apt-get apt dpkg-query sudo cmake ctest ninja; do
  printf '#!/bin/sh\necho "%s $*" >> "%s/calls"\nexit 1\n' "$cmd" "$stubs" >"$stubs/$cmd"
  chmod +x "$stubs/$cmd"
done
failed=0
check() {  # description, arguments...
  local what=$1
  shift
  local out code
  out=$(PATH="$stubs:$PATH" bash "$root/scripts/algray.sh" "$@" 2>&1)
  code=$?
  if [[ $code -ne 2 ]]; then
    echo "FAIL $what: exit code $code, expected 2; output: $out"
    failed=1
  fi
  if [[ $out != *"usage: bash scripts/algray.sh render|test"* ]]; then
    echo "FAIL $what: no usage line; output: $out"
    failed=1
  fi
  if [[ -e $stubs/calls ]]; then
    echo "FAIL $what: ran before checking its argument: $(tr '\n' ';' <"$stubs/calls")"
    rm -f "$stubs/calls"
    failed=1
  fi
}
check "a typo" rendr
check "no argument"
check "an empty argument" ""
check "a near miss of test" tests
if [[ $failed -eq 0 ]]; then echo "PASS"; fi
exit $failed
