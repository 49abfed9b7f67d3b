#!/usr/bin/env bash
# Fails when a C++ source of the repository differs from what clang-format (the
# repository's .clang-format) makes of it; lists the files. `scripts/check_format.sh --fix`
# formats them in place. Run by CTest (tests/code) and so by CI.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
fmt=${CLANG_FORMAT:-clang-format}
command -v "$fmt" >/dev/null || { echo "check_format: $fmt not found (scripts/install-deps.sh installs it)" >&2; exit 2; }
dirs=(mesher2d geom param surface io samples tests bench)
mapfile -t files < <(find "${dirs[@]}" -type f \( -name '*.cpp' -o -name '*.h' -o -name '*.hpp' \) \
  -not -path 'tests/fuzz/corpus/*' -not -path '*/node_modules/*' | sort)
if [ "${1:-}" = --fix ]; then
  "$fmt" -i "${files[@]}"
  exit 0
fi
mapfile -t bad < <("$fmt" --dry-run -Werror "${files[@]}" 2>&1 | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: error:.*/\1/p' | sort -u)
if [ ${#bad[@]} -gt 0 ]; then
  printf 'not clang-formatted: %s\n' "${bad[@]}" >&2
  echo "check_format: ${#bad[@]} of ${#files[@]} files; run scripts/check_format.sh --fix" >&2
  exit 1
fi
echo "check_format: ${#files[@]} files formatted"
