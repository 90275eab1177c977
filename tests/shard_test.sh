#!/usr/bin/env bash
# bake --library --shard (docs/scale-out.md): three shard processes, run at once into separate cache
# directories, bake disjoint sets of tables whose union is the unsharded bake, file for file and
# byte for byte; merging is copying, and the merged cache is what the unsharded bake, `bake
# --model` and `serve` reuse (same keys); bad input is one line, exit 2, and nothing written.
# Usage: shard_test.sh PATH/TO/ganzfeld
set -u
G="$1"
. "$(dirname "$0")/harness.sh"
N=3

# 14 distinct tables: 6 + 8 + a duplicate of the first group's minnaert h (baked once).
cat >"$tmp/lib.json" <<'EOF'
{"groups": [
  {"models": ["specular:alpha=8", "minnaert:xi=1", "0.5*lambert+0.5*specular:alpha=4"], "laws": ["g", "h"],
   "accuracies": [{"res_g": "9x9x5", "res_h": "17", "tol": 1e-6}]},
  {"models": ["minnaert:xi=0.5", "specular:alpha=8"], "laws": ["h", "a"],
   "accuracies": [{"res_h": "33", "tol": 1e-6, "encoding": "half"}, {"max_error": 1e-3}]},
  {"models": ["minnaert:xi=1"], "laws": ["h"], "accuracies": [{"res_h": 17, "tol": 1e-6}]}
]}
EOF
TABLES=14

# Each bake runs in its own directory with the relative --out cache, so the command stamped into
# each file (bake --model ... -o cache/NAME.exr) is the same whichever process baked it.
bake_in() {  # bake_in DIR [args]: bake the library into DIR/cache
  local dir="$1"; shift
  mkdir -p "$dir" && (cd "$dir" && "$G" bake --library ../lib.json --out cache --quiet "$@")
}
names() { ls "$1" | sort; }

bake_in "$tmp/all" --json >"$tmp/all.json" && ok || fail "unsharded bake: $(cat "$tmp/all.json")"
[ "$(json_field "$tmp/all.json" "(d['shard'], d['library_tables'], len(d['tables']))")" = "('0/1', $TABLES, $TABLES)" ] \
  && ok || fail "unsharded bake: $(head -c 300 "$tmp/all.json")"
[ "$(names "$tmp/all/cache" | wc -l)" -eq $TABLES ] && ok || fail "unsharded cache: $(names "$tmp/all/cache" | tr '\n' ' ')"

# --- N shard processes at once
pids=()
for ((k = 0; k < N; k++)); do bake_in "$tmp/s$k" --shard $k/$N >"$tmp/s$k.out" 2>&1 & pids+=($!); done
for ((k = 0; k < N; k++)); do wait "${pids[$k]}" && ok || fail "shard $k/$N: $(cat "$tmp/s$k.out")"; done
for ((k = 0; k < N; k++)); do
  [ "$(names "$tmp/s$k/cache" | wc -l)" -ge $((TABLES / N)) ] && ok || fail "shard $k/$N baked too few: $(cat "$tmp/s$k.out")"
  grep -q "^shard $k/$N: .* of the library's $TABLES tables" "$tmp/s$k.out" && ok || fail "shard $k summary: $(tail -1 "$tmp/s$k.out")"
done
for ((k = 0; k < N; k++)); do names "$tmp/s$k/cache"; done | sort >"$tmp/union"
[ -z "$(uniq -d "$tmp/union")" ] && ok || fail "shards overlap: $(uniq -d "$tmp/union" | tr '\n' ' ')"
names "$tmp/all/cache" >"$tmp/all.names"
cmp -s "$tmp/union" "$tmp/all.names" && ok || fail "union of shards != unsharded bake: $(diff "$tmp/union" "$tmp/all.names" | tr '\n' ' ')"
identical=0
for ((k = 0; k < N; k++)); do
  for f in "$tmp/s$k"/cache/*; do cmp -s "$f" "$tmp/all/cache/$(basename "$f")" && identical=$((identical + 1)) || fail "$f differs"; done
done
[ $identical -eq $TABLES ] && ok || fail "$identical of $TABLES shard files byte-identical to the unsharded bake"

# --- merging is copying: the merged cache is reused whole, by the library and by single bakes
mkdir -p "$tmp/merged/cache"
for ((k = 0; k < N; k++)); do cp "$tmp/s$k"/cache/* "$tmp/merged/cache/"; done
bake_in "$tmp/merged" --json >"$tmp/merged.json" && ok || fail "bake over the merged cache"
[ "$(json_field "$tmp/merged.json" "sorted(set(t['status'] for t in d['tables']))")" = "['reused']" ] \
  && ok || fail "merged cache not reused whole: $(json_field "$tmp/merged.json" "[t['status'] for t in d['tables']]")"
minnaert=$(cd "$tmp/merged/cache" && ls minnaert_xi=1.h.*.exr)
[ "$(echo "$minnaert" | wc -w)" -eq 1 ] && ok || fail "minnaert:xi=1 h: $minnaert"
[ "$(json_field <("$G" bake --model minnaert:xi=1 --law h --res 17 --tol 1e-6 -o "$tmp/merged/cache/$minnaert" --json) "d['tables'][0]['status']")" = reused ] \
  && ok || fail "bake --model does not reuse the library's entry (keys differ)"
[ -z "$(find "$tmp" -name '.*.tmp-*')" ] && ok || fail "temporary files left: $(find "$tmp" -name '.*.tmp-*')"

# --- docs/slurm/bake-library.sh as Slurm runs array task 1 of --array=0-2: shard 1/3, all reused
# from the merged cache; an array not numbered 0..N-1 is refused
mkdir -p "$tmp/bin" && ln -sf "$G" "$tmp/bin/ganzfeld"
slurm() { PATH="$tmp/bin:$PATH" SLURM_ARRAY_TASK_ID=1 SLURM_ARRAY_TASK_COUNT=3 "$@" \
  bash "$(dirname "$0")/../docs/slurm/bake-library.sh" "$tmp/lib.json" "$tmp/merged/cache"; }
slurm env SLURM_ARRAY_TASK_MIN=0 SLURM_ARRAY_TASK_MAX=2 >"$tmp/slurm.out" 2>&1 &&
  grep -q "^shard 1/3: .* of the library's $TABLES tables in .*: 0 baked" "$tmp/slurm.out" && ok || fail "slurm script: $(cat "$tmp/slurm.out")"
slurm env SLURM_ARRAY_TASK_MIN=1 SLURM_ARRAY_TASK_MAX=3 >"$tmp/slurm.out" 2>&1
[ $? -eq 2 ] && grep -q "submit with --array=0-2" "$tmp/slurm.out" && ok || fail "slurm script, array 1-3: $(cat "$tmp/slurm.out")"

# --- bad input: one line, exit 2, no directory and no file made
lib="$tmp/lib.json"
never="$tmp/never"
bad_lib() {  # bad_lib FRAGMENT JSON [extra args]: a library holding JSON is refused
  local fragment="$1" json="$2"; shift 2
  printf '%s' "$json" >"$tmp/bad.json"
  expect_bad "$fragment" bake --library "$tmp/bad.json" --out "$never" "$@"
}
for shard in 3/3 0/0 4/3 -1/3 1 a/b 1/2/3 "" 0/1x; do
  expect_bad "is not a shard; expected K/N with 0 <= K < N" bake --library "$lib" --out "$never" --shard "$shard"
done
expect_bad "library '$tmp/missing.json': no such file" bake --library "$tmp/missing.json" --out "$never"
bad_lib "malformed JSON" '{"groups": ['
bad_lib "expected {\"groups\"" '[]'
bad_lib "expected {\"groups\"" '{"groups": [], "extra": 1}'
bad_lib "groups[0].models: expected a non-empty array" '{"groups": [{"laws": ["h"]}]}'
bad_lib "groups[0].laws: expected a non-empty array" '{"groups": [{"models": ["lambert"], "laws": []}]}'
bad_lib "groups[0]: unknown key 'model'" '{"groups": [{"model": ["lambert"], "laws": ["h"]}]}'
bad_lib "groups[0].models[1]: unknown model 'nope'" '{"groups": [{"models": ["lambert", "nope"], "laws": ["h"]}]}'
bad_lib "groups[0].models[0]: 3 is not a string" '{"groups": [{"models": [3], "laws": ["h"]}]}'
bad_lib "groups[0].laws[0]: law 'f' has no table; allowed: g, h, a" '{"groups": [{"models": ["lambert"], "laws": ["f"]}]}'
bad_lib "is anisotropic" '{"groups": [{"models": ["ward-aniso:alpha_x=0.1,alpha_y=0.3"], "laws": ["h"]}]}'
bad_lib "accuracies[0]: unknown key 'res'" '{"groups": [{"models": ["lambert"], "laws": ["h"], "accuracies": [{"res": "9"}]}]}'
bad_lib "accuracies[0]: res_g='1x1' is not a resolution for law g" '{"groups": [{"models": ["lambert"], "laws": ["g"], "accuracies": [{"res_g": "1x1"}]}]}'
bad_lib "accuracies[1]: max_error chooses the resolution and the tolerance itself; drop res_h or max_error" '{"groups": [{"models": ["lambert"], "laws": ["h"], "accuracies": [{}, {"max_error": 1e-3, "res_h": "9"}]}]}'
bad_lib "accuracies[0].tol: \"small\" is not a number" '{"groups": [{"models": ["lambert"], "laws": ["h"], "accuracies": [{"tol": "small"}]}]}'
bad_lib "not expected: 9x9x5 --res-g" "$(cat "$lib")" --res-g 9x9x5
expect_bad "not expected: 0/2 --shard" bake --scene "$(dirname "$0")/../examples/default.json" --out "$never" --shard 0/2
expect_bad "At Most 1" bake --library "$lib" --scene x.json --out "$never"
expect_bad "bake library needs --out DIR" bake --library "$lib"
[ ! -e "$never" ] && ok || fail "a refused bake created $never"

echo "shard: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
