#!/usr/bin/env bash
# Lists the tracked C++ files that clang-format (with the repository's .clang-format) would change and
# exits 1 when there is any. Changes nothing.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../version.sh"
hg_answer_version check-format "$@"

usage() {
  cat <<'USAGE'
usage: tools/lint/check-format.sh [--fix] [FILE...]

Runs clang-format with the repository's .clang-format on every *.cpp/*.hpp `git ls-files` lists (or on
the FILEs given) and lists the files it would change, exiting 1 if there is one, 0 if none. Changes
nothing unless --fix is given, which reformats those files in place.
Needs clang-format (Debian package clang-format; tools/install-deps.sh installs it).

  --fix      reformat the files in place instead of listing them
  -h, --help this text
USAGE
}

fix=0
files=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --fix) fix=1; shift ;;
    -*) echo "check-format: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) files+=("$1"); shift ;;
  esac
done

command -v clang-format >/dev/null || { echo "check-format: clang-format not found (apt-get install clang-format)" >&2; exit 2; }
# FILE arguments are taken relative to where the script was called from.
for i in "${!files[@]}"; do files[$i]=$(realpath -- "${files[$i]}"); done
cd "$(dirname "$0")/../.."
[[ -f .clang-format ]] || { echo "check-format: no .clang-format at $(pwd)" >&2; exit 2; }
if [[ ${#files[@]} -eq 0 ]]; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp')
fi

if [[ $fix -eq 1 ]]; then
  clang-format -i --style=file "${files[@]}"
  exit 0
fi

bad=()
for f in "${files[@]}"; do
  if ! clang-format --style=file --dry-run -Werror "$f" >/dev/null 2>&1; then bad+=("$f"); fi
done
if [[ ${#bad[@]} -gt 0 ]]; then
  echo "check-format: ${#bad[@]} of ${#files[@]} files are not formatted (tools/lint/check-format.sh --fix):" >&2
  printf '  %s\n' "${bad[@]}" >&2
  exit 1
fi
echo "check-format: all ${#files[@]} files formatted"
