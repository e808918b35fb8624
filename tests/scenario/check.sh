# Shared by the shell tests here: `check <description> <command...>` runs the command and counts
# it in $passes or $fails, printing "FAIL: <description>" when it fails. Source it, then end with
# `echo "<test>: $passes passed, $fails failed"; [ "$fails" -eq 0 ]`.
fails=0
passes=0
check() {
  local what=$1
  shift
  if "$@"; then
    passes=$((passes + 1))
  else
    echo "FAIL: $what"
    fails=$((fails + 1))
  fi
}
