#!/usr/bin/env bash
# The longest functions outside tests (issue 17's table): lines from a function's opening line to its
# end, as universal-ctags sees them (apt-get install universal-ctags). Usage: function_lengths.sh [N]
# (default 10) from the repository root. Lambdas count towards the function that holds them.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
command -v ctags >/dev/null || { echo "function_lengths.sh: needs universal-ctags (apt-get install universal-ctags)" >&2; exit 1; }
dirs=()
for d in core continuum discrete compare studies apps bench; do [[ -d $d ]] && dirs+=("$d"); done
ctags -R --languages=C++ --langmap=C++:+.hpp --kinds-C++=f --fields=+ne -x \
  --_xformat="%{end}	%{line}	%{input}	%{scope}	%{name}" "${dirs[@]}" 2>/dev/null |
  awk -F'\t' '$1 ~ /^[0-9]+$/ { s = $4; sub(/^slipfront::/, "", s); gsub(/(::)?__anon[0-9a-f]+/, "", s);
        printf "%5d  %s:%d  %s%s\n", $1 - $2 + 1, $3, $2, (s == "" ? "" : s "::"), $5 }' |
  sort -rn | head -n "${1:-10}"
