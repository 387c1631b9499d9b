# Shared by the tool's shell tests (cli_test.sh, batch_test.sh, slurm_test.sh): `expect` and the pass/fail tally.
# Source it, then call expect; end with `finish`.
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

# finish: prints the tally; the exit status is 0 only when nothing failed.
finish() {
  echo "$passed passed, $failed failed"
  [ "$failed" -eq 0 ]
}
