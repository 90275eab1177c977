#!/usr/bin/env bash
# Fails on a back arrow: every #include "MODULE/..." in a module must name the module itself or
# one it may depend on (docs/architecture.md). The build enforces the same through staged include
# directories; this states the arrows in one place. Usage: layering_test.sh SOURCE_DIR
set -uo pipefail
cd "$1"
declare -A allowed=(
  [util]="util"
  [laws]="util laws"
  [integrate]="util laws integrate"
  [tables]="util laws integrate tables"
  [scene]="util laws integrate tables scene"
  [export]="util laws integrate tables scene export"
  [reports]="util laws integrate tables reports"
  [rasterizer]="util laws integrate tables scene rasterizer"
  [bench]="util laws integrate tables scene rasterizer reports bench"
  [cli]="util laws integrate tables scene export reports rasterizer bench cli"
  [fuzz]="util laws integrate tables scene export reports rasterizer bench cli fuzz"
)
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
for dir in */; do
  dir=${dir%/}
  [ -n "${allowed[$dir]+x}" ] || [[ "$dir" =~ ^(tests|docs|examples|scripts|cmake|build.*)$ ]] ||
    { echo "layering: folder $dir/ is not a declared module (add it to tests/layering_test.sh)"; status=1; }
done
[ $status -eq 0 ] && echo "layering: ok (${#allowed[@]} modules)"
exit $status
