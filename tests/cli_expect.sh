# Sourced by the CLI test scripts: the expect helper and its counters (print "$passed passed, $failed failed" last).
passed=0
failed=0

# expect NAME CODE PATTERN -- COMMAND...: runs COMMAND, checks the exit code and that stderr+stdout match PATTERN.
expect() {
  local name=$1 code=$2 pattern=$3
  shift 4
  local out rc
  out=$("$@" 2>&1)
  rc=$?
  if [ "$rc" -eq "$code" ] && grep -qE -- "$pattern" <<<"$out"; then
    passed=$((passed + 1))
  else
    failed=$((failed + 1))
    echo "FAIL $name: exit $rc (want $code), output (want /$pattern/):"
    sed 's/^/    /' <<<"$out" | head -n 20
  fi
}

