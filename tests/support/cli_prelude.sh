# Sourced by the command-line test scripts (tests/cli/*.sh), with their arguments:
#   source "$(dirname "$0")/../support/cli_prelude.sh" "$@"
# Sets tool (the ambdrop binary) and source_dir, strict mode, and a scratch directory `work`
# that is the current directory and is removed on exit; fail prints and exits 1.
set -euo pipefail
tool=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*" >&2
  exit 1
}
cd "$work"
# The independent generator's binary: the script's third argument, else tools/truth/ambdrop_truth
# beside the ambdrop binary's build tree; without one the script skips (exit 77), saying why.
# Sets truth_tool.
find_truth_tool_or_skip() {
  truth_tool=${1:-}
  if [[ -z $truth_tool ]]; then
    for candidate in "$(dirname "$tool")/truth/ambdrop_truth" \
      "$(dirname "$tool")/tools/truth/ambdrop_truth"; do
      [[ -x $candidate ]] && truth_tool=$candidate && break
    done
  fi
  [[ -n $truth_tool && -x $truth_tool ]] || {
    echo "SKIP: no ambdrop_truth binary (pass it as the third argument)"
    exit 77
  }
}
