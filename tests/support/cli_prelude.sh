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
