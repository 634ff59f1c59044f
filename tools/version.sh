# Sourced by the shell scripts in tools/ (not run): what --version and --help print.
# hg_version: the project's version, from CMakeLists.txt's project() (the one place it is written).
hg_version() { sed -n 's/^project(hullgrind VERSION \([0-9.]*\).*/\1/p' "$(dirname "${BASH_SOURCE[0]}")/../CMakeLists.txt"; }
# hg_comment_help FILE: the script's leading comment block (after the #! line), as its --help text.
hg_comment_help() { sed -n '2,/^[^#]/{/^#/{s/^# \{0,1\}//;p}}' "$1"; }
# hg_answer NAME FILE ARGS...: answers --version, and --help from the comment block, then exits 0; otherwise
# returns. For scripts without a usage text of their own.
hg_answer() {
  local name=$1 file=$2
  shift 2
  for a in "$@"; do
    case "$a" in
      --version) echo "$name $(hg_version)"; exit 0 ;;
      --help|-h) hg_comment_help "$file"; exit 0 ;;
    esac
  done
}
# hg_answer_version NAME ARGS...: for scripts with a usage text of their own: answers --version only.
hg_answer_version() {
  local name=$1
  shift
  for a in "$@"; do [[ "$a" != --version ]] || { echo "$name $(hg_version)"; exit 0; }; done
}
