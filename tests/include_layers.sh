#!/usr/bin/env bash
# Includes run downwards only (DESIGN.md, "Layout"): apps, render, scenes, runtime, kernels,
# then builders and traversal side by side (never including each other), then device. A file
# may include its own layer and any layer below it, and the public header from anywhere.
#   tests/include_layers.sh [ROOT]
set -uo pipefail
root=${1:-$(dirname "$0")/..}
cd "$root"
rank() {
  case $1 in
    apps/*) echo 0 ;; render/*) echo 1 ;; scenes/*) echo 2 ;; runtime/*) echo 3 ;; kernels/*) echo 4 ;;
    builders/*) echo 5b ;; traversal/*) echo 5t ;; device/*) echo 6 ;; *) echo - ;;
  esac
}
level() { echo "${1%[bt]}"; }
bad=0 checked=0
for file in $(git ls-files 'apps/*' 'render/*' 'scenes/*' 'runtime/*' 'kernels/*' 'builders/*' 'traversal/*' 'device/*' |
              grep -E '\.(c|h|cl)$'); do
  from=$(rank "$file")
  while read -r inc; do
    to=$(rank "$inc")
    [ "$to" = - ] && continue
    checked=$((checked + 1))
    if [ "$(level "$to")" -lt "$(level "$from")" ]; then
      echo "up: $file includes $inc"; bad=1
    elif [ "$(level "$to")" = "$(level "$from")" ] && [ "$to" != "$from" ]; then
      echo "sideways: $file includes $inc (builders and traversal never include each other)"; bad=1
    fi
  done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$file")
done
echo "$checked includes checked"
exit $bad
