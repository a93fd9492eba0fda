#!/usr/bin/env bash
# clang-format check of the C++ files changed since tools/format_base (the commit from which the
# style is enforced): every file touched after it must match .clang-format, so the code converges
# on one layout without one commit that reformats everything.
# Usage: tools/check_format.sh [--fix]. Exit 0: clean; 1: files differ (listed); 77: cannot check
# (no clang-format, or the base commit is not in this clone's history), which ctest reports as skipped.
set -euo pipefail
cd "$(dirname "$0")/.."
fix=0
[ "${1:-}" = --fix ] && fix=1
tool="$(command -v clang-format || command -v clang-format-14 || true)"
if [ -z "$tool" ]; then echo "check_format: clang-format not installed (apt-get install clang-format)"; exit 77; fi
base="$(tr -d ' \n' < tools/format_base)"
if ! git rev-parse -q --verify "$base^{commit}" >/dev/null 2>&1; then
  echo "check_format: base commit $base is not in this clone's history (shallow clone?)"; exit 77
fi
# Changed since the base, committed or not, and still present; untracked new files count too.
mapfile -t files < <({ git diff --name-only "$base" -- '*.cpp' '*.hpp' '*.h' '*.cc';
                       git ls-files --others --exclude-standard -- '*.cpp' '*.hpp' '*.h' '*.cc'; } |
                     sort -u | while read -r f; do [ -f "$f" ] && echo "$f"; done)
[ "${#files[@]}" -eq 0 ] && { echo "check_format: no C++ file changed since $base"; exit 0; }
if [ "$fix" = 1 ]; then "$tool" -i "${files[@]}"; echo "check_format: formatted ${#files[@]} files"; exit 0; fi
bad=()
for f in "${files[@]}"; do
  "$tool" --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ "${#bad[@]}" -gt 0 ]; then
  echo "check_format: ${#bad[@]} of ${#files[@]} changed files differ from .clang-format (fix: tools/check_format.sh --fix):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "check_format: ${#files[@]} changed files match .clang-format"
