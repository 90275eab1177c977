#!/usr/bin/env bash
# `ganzfeld export-glsl --texture header` as an engine uses it: the C header compiles as C11 and as
# C++17 (gcc and g++, warnings as errors), and a lookup in the compiled-in texels
# (tests/header_lookup.c) agrees with `ganzfeld sample` at seeded points, for float, half and unorm16
# tables of g and h. Usage: header_export_test.sh PATH/TO/ganzfeld
set -u
G="$1"
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/harness.sh"
# The two lookups read the same stored numbers: they differ by double rounding in the coordinates
# and the blend (a wrong texel order, mapping or decoding moves a lookup by a sizeable part of the
# step between nodes, > 1e-4).
tolerance=1e-9
points=12

# check NAME LAW BAKE-ARGS...: bake, export the header, compile and compare.
check() {
  local name="$1" law="$2"; shift 2
  "$G" bake --law "$law" "$@" --tol 1e-6 -o "$tmp/$name.exr" --quiet >/dev/null || { fail "bake $name"; return; }
  "$G" export-glsl "$tmp/$name.exr" -o "$tmp/$name.glsl" --texture header --quiet || { fail "export $name"; return; }
  "$G" info "$tmp/$name.exr" --json >"$tmp/$name.json" || { fail "info $name"; return; }
  local symbol encoding define="" axes
  symbol=$(sed -nE 's/^static const (float|uint16_t) ([A-Za-z0-9_]+)_texels\[.*/\2/p' "$tmp/$name.h")
  encoding=$(json_field "$tmp/$name.json" "d['encoding']")
  [ "$encoding" = half ] && define=-DGZ_HALF
  [ "$encoding" = unorm16 ] && define=-DGZ_UNORM16
  axes=$(json_field "$tmp/$name.json" "' '.join('%s %r %r' % (a['mapping'], a['min'], a['max']) for a in d['axes'])")
  [ "$(json_field "$tmp/$name.json" "d['frame'] + ' ' + d['interpolation']")" = "cosines linear" ] \
    || { fail "$name: the C lookup is the cosines frame's linear one"; return; }
  local binary outputs=()
  for compiler in "gcc -std=c11 -x c" "g++ -std=c++17 -x c++"; do
    binary="$tmp/${name}_${compiler%% *}"
    # shellcheck disable=SC2086
    if ! $compiler -Wall -Wextra -Wpedantic -Werror -O1 "-DGZ_HEADER=\"$tmp/$name.h\"" "-DGZ_SYMBOL=$symbol" $define \
        "$here/header_lookup.c" -x none -lm -o "$binary" 2>"$tmp/cc.log"; then
      fail "$name.h does not compile with $compiler: $(head -5 "$tmp/cc.log")"
      return
    fi
    ok
    # shellcheck disable=SC2086
    "$binary" "$law" "$points" 26 $axes >"$binary.points" || { fail "$binary failed"; return; }
    outputs+=("$binary.points")
  done
  cmp -s "${outputs[0]}" "${outputs[1]}" && ok || fail "$name: the C11 and C++17 lookups differ"
  local worst=0 line value sampled
  while read -r line; do
    value=${line##* }
    # shellcheck disable=SC2086
    sampled=$("$G" sample "$tmp/$name.exr" ${line% *} --json | python3 -c "import json,sys; print(json.load(sys.stdin)['value'])")
    worst=$(python3 -c "print(max($worst, abs($value - $sampled)))")
  done <"${outputs[0]}"
  [ "$(wc -l <"${outputs[0]}")" -eq "$points" ] && python3 -c "import sys; sys.exit(0 if $worst <= $tolerance else 1)" \
    && ok || fail "$name: max |header lookup - ganzfeld sample| = $worst > $tolerance over $points points"
}

check g_float g --model specular:alpha=8 --res 9x9x5
check g_half g --model specular:alpha=8 --res 9x9x5 --encoding half
check g_unorm g --model backscatter:alpha=4 --res 7x9x6 --encoding unorm16
check h_float h --model minnaert:xi=0.5 --res 17
check h_unorm h --model asperity:alpha=4 --res 12 --encoding unorm16
echo "header export: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
