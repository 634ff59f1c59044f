#!/usr/bin/env bash
# Lists the functions of the product code longer than the limit, longest first, and exits 1 when there
# is any: C++ (every tracked *.cpp/*.hpp outside tests/) and Python (tracked *.py and python-shebang
# scripts outside tests/). Extents come from universal-ctags (`ctags --fields=+ne`: line and end). A
# lambda or nested function counts as part of the function around it.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/../version.sh"
hg_answer_version check-function-length "$@"

usage() {
  cat <<'USAGE'
usage: tools/lint/check-function-length.sh [--max N] [FILE...]

Lists C++ and Python functions longer than N lines (default 80; the length is end line - start line,
as ctags reports them) as "LINES FILE:LINE FUNCTION", longest first, and exits 1 if there is one, 0 if
none. Without FILE arguments it checks the product code: every tracked *.cpp and *.hpp file, *.py file
and python-shebang script outside tests/. A FILE ending in .py or starting with a python shebang is
read as Python, any other as C++.
Needs universal-ctags (Debian package universal-ctags; tools/install-deps.sh installs it).

  --max N    the longest allowed function, in lines (default 80)
  -h, --help this text
USAGE
}

max=80
files=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h|--help) usage; exit 0 ;;
    --max) [[ $# -ge 2 && "$2" =~ ^[0-9]+$ ]] || { echo "check-function-length: --max needs a number" >&2; exit 2; }
           max=$2; shift 2 ;;
    -*) echo "check-function-length: unknown option $1 (see --help)" >&2; exit 2 ;;
    *) files+=("$1"); shift ;;
  esac
done

if ! ctags --version 2>/dev/null | grep -q 'Universal Ctags'; then
  echo "check-function-length: universal-ctags not found (apt-get install universal-ctags)" >&2
  exit 2
fi

# FILE arguments are taken relative to where the script was called from.
for i in "${!files[@]}"; do files[$i]=$(realpath -- "${files[$i]}"); done
cd "$(dirname "$0")/../.."
if [[ ${#files[@]} -eq 0 ]]; then
  mapfile -t files < <(git ls-files | grep -v '^tests/' | grep -E '\.(cpp|hpp|py)$|^tools/[^.]*$')
fi
cpp=()
py=()
for f in "${files[@]}"; do
  [[ -f "$f" ]] || continue
  if [[ "$f" == *.py ]] || head -c 64 "$f" | head -n 1 | grep -q '^#!.*python'; then py+=("$f")
  elif [[ "$f" == *.cpp || "$f" == *.hpp || "$f" == *.h || "$f" == *.cc ]]; then cpp+=("$f")
  fi
done
[[ $(( ${#cpp[@]} + ${#py[@]} )) -gt 0 ]] || { echo "check-function-length: no files to check" >&2; exit 2; }

tags() {
  [[ ${#cpp[@]} -eq 0 ]] || ctags --languages=C++ --kinds-C++=f --fields=+ne -f - "${cpp[@]}"
  [[ ${#py[@]} -eq 0 ]] || ctags --language-force=Python --kinds-Python=fm --fields=+ne -f - "${py[@]}"
}

long=$(tags |
  awk -F'\t' -v max="$max" '{
      l = e = 0
      for (i = 4; i <= NF; i++) {
        if ($i ~ /^line:/) l = substr($i, 6)
        if ($i ~ /^end:/) e = substr($i, 5)
      }
      if (e - l > max) printf "%d %s:%d %s\n", e - l, $2, l, $1
    }' | sort -rn)

if [[ -n "$long" ]]; then
  echo "check-function-length: functions longer than $max lines:" >&2
  echo "$long" >&2
  exit 1
fi
echo "check-function-length: no function longer than $max lines in ${#cpp[@]} C++ and ${#py[@]} Python files"
