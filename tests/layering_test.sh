#!/usr/bin/env bash
# Fails on a back arrow: every #include "MODULE/..." in a module must name the module itself or
# one it may depend on (docs/architecture.md). The build enforces the same through staged include
# directories; this states the arrows in one place. Usage: layering_test.sh SOURCE_DIR
set -uo pipefail
cd "$1"
# The arrows: each module and the modules it builds on directly (docs/architecture.md, "The rooms").
declare -A arrows=(
  [util]="" [models]="util" [reference]="models" [integrate]="models" [tables]="integrate" [scene]="tables" [export]="scene"
  [shapes]="tables" [serve]="export shapes rasterizer" [reports]="tables reference" [rasterizer]="scene" [gl]="export" [bench]="rasterizer reports gl"
  [fit]="export reports" [cli]="serve reports bench fit" [fuzz]="cli" [python]="shapes reports"
)
# What a module may use: itself and everything its arrows reach.
declare -A allowed
reach() {
  local module=$1 next
  for next in ${arrows[$module]}; do
    [[ " ${allowed[$2]} " == *" $next "* ]] && continue
    allowed[$2]+=" $next"
    reach "$next" "$2"
  done
}
for module in "${!arrows[@]}"; do
  allowed[$module]=" $module"
  reach "$module" "$module"
done
status=0
for module in "${!allowed[@]}"; do
  [ -d "$module" ] || { echo "layering: module folder $module/ is missing"; status=1; continue; }
  while IFS=: read -r file line include; do
    target=$(sed -E 's/.*#include "([^/"]+)\/.*/\1/' <<<"$include")
    [[ " ${allowed[$module]} " == *" $target "* ]] && continue
    echo "layering: $file:$line includes $target/ but $module/ may use only: ${allowed[$module]}"
    status=1
  done < <(grep -nE '^#include "[^/"]+/' "$module"/*.h "$module"/*.cpp 2>/dev/null)
done
for dir in */; do  # js/: the npm packages (not C++; docs/architecture.md)
  dir=${dir%/}
  [ -n "${allowed[$dir]+x}" ] || [[ "$dir" =~ ^(tests|docs|examples|js|scripts|cmake|out|build.*)$ ]] ||
    { echo "layering: folder $dir/ is not a declared module (add it to tests/layering_test.sh)"; status=1; }
done
[ $status -eq 0 ] && echo "layering: ok (${#allowed[@]} modules)"
exit $status
