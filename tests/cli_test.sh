#!/usr/bin/env bash
# The command line as users and scripts see it: exit codes, one-line errors
# on stderr, JSON on stdout, no partial output files. Usage: cli_test.sh PATH/TO/ganzfeld
set -u
G="$1"
. "$(dirname "$0")/harness.sh"

# --- help and version
"$G" --help >/dev/null && ok || fail "--help"
"$G" eval --help | grep -q -- "--theta-i" && ok || fail "eval --help"

# --- models
"$G" models --json >"$tmp/models.json" && ok || fail "models --json"
[ "$(json_field "$tmp/models.json" "len(d['models'])")" -ge 6 ] && ok || fail "models count"
[ "$(json_field "$tmp/models.json" "[m['reciprocal'] for m in d['models'] if m['name']=='specular'][0]")" = "True" ] && ok || fail "models traits"

# docs/model-parameters.md is generated from the registry and kept current
"$G" models --markdown "$tmp/model-parameters.md" && ok || fail "models --markdown"
cmp -s "$tmp/model-parameters.md" "$(dirname "$0")/../docs/model-parameters.md" && ok \
  || fail "docs/model-parameters.md is stale: run ganzfeld models --markdown docs/model-parameters.md"
expect_bad "cannot write" models --markdown "$tmp/no/such/dir/p.md"

# --- eval: the Core acceptance command
"$G" eval --model specular:alpha=1000 --law g --theta-i 60 --theta-j 30 --phi 180 --tol 1e-10 --json >"$tmp/eval.json" 2>"$tmp/err" \
  && ok || fail "eval acceptance"
[ "$(json_field "$tmp/eval.json" "d['converged'] and d['error'] <= 1e-10 and d['law']=='g' and d['model']=='specular:alpha=1000'")" = "True" ] \
  && ok || fail "eval acceptance JSON: $(cat "$tmp/eval.json")"
[ ! -s "$tmp/err" ] && ok || fail "eval wrote to stderr"
# f: error 0, one evaluation; h of Lambert is 1
[ "$(json_field <("$G" eval --model lambert --law f --theta-i 10 --theta-j 20 --json) "d['error']==0 and d['evaluations']==1")" = "True" ] && ok || fail "eval f"
[ "$(json_field <("$G" eval --model lambert --law h --j 0,0.3,1 --json) "abs(d['value']-1)<1e-12")" = "True" ] && ok || fail "eval h"
# non-convergence is a reported result (exit 0, converged false, a warning on stderr)
"$G" eval --model specular:alpha=1000 --law g --theta-i 60 --theta-j 30 --phi 180 --tol 1e-15 --max-evals 2000 --json >"$tmp/nc.json" 2>/dev/null
[ "$(json_field "$tmp/nc.json" "d['converged']")" = "False" ] && ok || fail "non-convergence not reported"

# --- bad input
expect_bad "unknown model 'no-such-model'" eval --model no-such-model --law g --theta-i 1 --theta-j 1
expect_bad "alpha=0" eval --model specular:alpha=0 --law h --theta-j 1
expect_bad "alpha=nan" eval --model specular:alpha=nan --law h --theta-j 1
expect_bad "unknown parameter 'beta'" eval --model specular:beta=1 --law h --theta-j 1
expect_bad "KEY=VALUE" eval --model specular:alpha --law h --theta-j 1
expect_bad "unknown law 'x'" eval --model lambert --law x
expect_bad "--theta-j=95" eval --model lambert --law h --theta-j 95
expect_bad "--theta-i=100" eval --model lambert --law a --theta-i 100
# extremes --keep: a file in the way is refused before the grid runs; a kept row of other options too
: >"$tmp/keep-file"
expect_bad "--keep '$tmp/keep-file' is not a directory" extremes --quick --model lambert --keep "$tmp/keep-file"
"$G" extremes --quick --model lambert --keep "$tmp/kept" >/dev/null && [ -s "$tmp/kept/lambert.json" ] && ok \
  || fail "extremes --keep keeps the model's row"
expect_bad "measured with options" extremes --quick --model lambert --tol 1e-7 --keep "$tmp/kept"
expect_bad "--theta-i=181" eval --model lambert --law g --theta-i 181 --theta-j 0
expect_bad "zero length" eval --model lambert --law h --j 0,0,0
expect_bad "three finite numbers" eval --model lambert --law h --j 1,2
expect_bad "below the surface" eval --model lambert --law h --j 0,0,-1
expect_bad "--tol 0 is not allowed" eval --model lambert --law h --theta-j 1 --tol 0
expect_bad "--tol nan is not allowed" eval --model lambert --law h --theta-j 1 --tol nan
expect_bad "needs the view direction" eval --model lambert --law h
expect_bad "not expected" eval --model lambert --law h --theta-j 1 --no-such-flag
expect_bad "cannot write" verify --markdown "$tmp/no/such/dir/errata.md"
[ ! -e "$tmp/no/such/dir/errata.md" ] && ok || fail "partial errata file"

# --- plausibility: JSON shape, the Lambert row, refusals
"$G" plausibility --json >"$tmp/plaus.json" && ok || fail "plausibility --json"
[ "$(json_field "$tmp/plaus.json" "[m for m in d['models'] if m['spec']=='lambert'][0]['ganzfeld_invisible'] and all(m['traits_consistent'] for m in d['models'])")" = "True" ] \
  && ok || fail "plausibility JSON"
expect_bad "tolerance" plausibility --tol -1
expect_bad "cannot write" plausibility --markdown "$tmp/no/such/dir/p.md"

# --- verify
"$G" verify --json --markdown "$tmp/errata.md" >"$tmp/verify.json" && ok || fail "verify exit code"
[ "$(json_field "$tmp/verify.json" "len(d['checks'])>=24 and all(c['status'] in ('matches','erratum') for c in d['checks'])")" = "True" ] && ok || fail "verify JSON"
[ "$(json_field "$tmp/verify.json" "all((c['corrected_max_abs_error'] if c['status']=='erratum' else c['max_abs_error']) <= 1e-9 for c in d['checks'])")" = "True" ] && ok || fail "verify agreement"
grep -q "minnaert.g.hyp2f1" "$tmp/errata.md" && ok || fail "errata markdown"
ls -a "$tmp" | grep -q '\.tmp-' && fail "temporary file left behind" || ok

# --- parameter tables: bake --preset, info and sample at (alpha | roughness, mu), eval --alpha
"$G" bake --preset dfg --model ggx --res 4x5 -o "$tmp/dfg.exr" >/dev/null && ok || fail "bake --preset dfg"
[ "$(json_field <("$G" info "$tmp/dfg.exr" --json) "d['format_version']==3 and [a['name'] for a in d['axes']]==['roughness','cos_theta_i'] and [c['name'] for c in d['channels']]==['dfg_fc','dfg_e','charlie'] and d['axes'][1]['grid']=='texel' and d['max_error']<=1e-6")" = "True" ] \
  && ok || fail "info of a dfg table"
[ "$(json_field <("$G" sample "$tmp/dfg.exr" --roughness 0.5 --mu 0.5 --json) "abs(d['alpha']-0.25)<1e-15 and len(d['channels'])==3")" = "True" ] && ok || fail "sample --roughness"
[ "$(json_field <("$G" sample "$tmp/dfg.exr" --alpha 0.25 --theta-i 60 --json) "abs(d['mu']-0.5)<1e-12")" = "True" ] && ok || fail "sample --alpha --theta-i"
"$G" bake --preset kulla-conty --model ggx:g2=separable --res 3 --grid node --axis alpha -o "$tmp/kc.exr" >/dev/null && ok || fail "bake --preset kulla-conty"
[ "$(json_field <("$G" info "$tmp/kc.exr" --json) "[c['name'] for c in d['channels']]==['e','e_avg'] and d['axes'][0]['name']=='alpha'")" = "True" ] && ok || fail "info of a kulla-conty table"
[ "$(json_field <("$G" eval --model ggx:alpha=0.9,f0=1 --alpha 1 --law a --theta-i 0 --json) "d['model'].startswith('ggx:alpha=1,')")" = "True" ] && ok || fail "eval --alpha overrides"
"$G" export-glsl "$tmp/dfg.exr" -o "$tmp/dfg.glsl" >/dev/null && grep -q "vec4 gz_dfg_filament(highp sampler2D table, float mu, float roughness)" "$tmp/dfg.glsl" \
  && grep -q "gz_dfg_filament_texels\[60\]" "$tmp/dfg.h" && ok || fail "export-glsl of a dfg table"
expect_bad "--texture ktx2 is not available for parameter tables" export-glsl "$tmp/dfg.exr" -o "$tmp/dfg2.glsl" --texture ktx2
expect_bad "'lambert' has no parameter roughness" bake --preset dfg --model lambert -o "$tmp/bad.exr"
expect_bad "is defined for ggx" bake --preset kulla-conty --model ggx-ms -o "$tmp/bad.exr"
expect_bad "sets alpha" bake --preset dfg --model ggx:alpha=0.3 -o "$tmp/bad.exr"
expect_bad "unknown preset 'dfgx'" bake --preset dfgx --model ggx -o "$tmp/bad.exr"
expect_bad "--axis 'beta'" bake --preset dfg --model ggx --axis beta -o "$tmp/bad.exr"
expect_bad "unknown grid" bake --preset dfg --model ggx --grid centre -o "$tmp/bad.exr"
expect_bad "not a preset resolution" bake --preset dfg --model ggx --res 1 -o "$tmp/bad.exr"
expect_bad "--dfg-layout is for bake preset dfg" bake --preset kulla-conty --dfg-layout ue4 --model ggx -o "$tmp/bad.exr"
expect_bad "not expected: a --law" bake --preset dfg --model ggx --law a -o "$tmp/bad.exr"
[ ! -e "$tmp/bad.exr" ] && ok || fail "a refused preset bake left a file"
expect_bad "--alpha=0 " sample "$tmp/dfg.exr" --alpha 0 --mu 0.5
expect_bad "--alpha=1.5" sample "$tmp/dfg.exr" --alpha 1.5 --mu 0.5
expect_bad "--alpha=nan" sample "$tmp/dfg.exr" --alpha nan --mu 0.5
expect_bad "--roughness=1.2" sample "$tmp/dfg.exr" --roughness 1.2 --mu 0.5
expect_bad "--roughness=-0.1" sample "$tmp/dfg.exr" --roughness -0.1 --mu 0.5
expect_bad "--mu=2" sample "$tmp/dfg.exr" --roughness 0.5 --mu 2
expect_bad "needs --alpha A or --roughness R" sample "$tmp/dfg.exr" --mu 0.5
expect_bad "has no parameter alpha" eval --model lambert --alpha 0.5 --law a --theta-i 10
expect_bad "--alpha=-1" eval --model ggx --alpha -1 --law a --theta-i 10
expect_bad "roughness=0" eval --model ggx --roughness 0 --law a --theta-i 10

# --- bake --scene: only the tables the scene needs, cached; the second run bakes nothing
scene="$(dirname "$0")/../examples/default.json"
tiny=(--res-g 3x3x3 --res-h 5 --tol 1e-6)
"$G" bake --scene "$scene" --out "$tmp/cache" "${tiny[@]}" --json >"$tmp/scene1.json" && ok || fail "scene bake"
[ "$(json_field "$tmp/scene1.json" "len(d['tables'])==6 and all(t['status']=='baked' for t in d['tables']) and sorted(set(t['law'] for t in d['tables']))==['g','h']")" = "True" ] \
  && ok || fail "scene bake JSON: $(cat "$tmp/scene1.json")"
"$G" bake --scene "$scene" --out "$tmp/cache" "${tiny[@]}" --json >"$tmp/scene2.json" && ok || fail "scene bake again"
[ "$(json_field "$tmp/scene2.json" "len(d['tables'])==6 and all(t['status']=='reused' for t in d['tables'])")" = "True" ] \
  && ok || fail "second scene bake not all reused: $(cat "$tmp/scene2.json")"
[ "$(ls "$tmp/cache" | wc -l)" -eq 6 ] && ok || fail "cache holds $(ls -a "$tmp/cache")"
"$G" bake --model specular:alpha=8 --law h --res 5 --tol 1e-6 -o "$tmp/h.exr" --json >/dev/null && ok || fail "single bake"
[ "$(json_field <("$G" bake --model specular:alpha=8 --law h --res 5 --tol 1e-6 -o "$tmp/h.exr" --json) "d['tables'][0]['status']")" = "reused" ] \
  && ok || fail "single bake not reused"
[ "$(json_field <("$G" bake --model specular:alpha=8 --law h --res 6 --tol 1e-6 -o "$tmp/h.exr" --json) "d['tables'][0]['status']")" = "baked" ] \
  && ok || fail "single bake with another key reused"
echo '{"lights": [{"type": "spot"}]}' >"$tmp/bad_scene.json"
expect_bad '"spot"' bake --scene "$tmp/bad_scene.json" --out "$tmp/cache2"
[ ! -e "$tmp/cache2" ] && ok || fail "bad scene created its --out"
expect_bad "does not exist" bake --scene "$scene" --out "$tmp/no/such/cache" "${tiny[@]}"
[ ! -e "$tmp/no" ] && ok || fail "--out under a missing parent created something"
expect_bad "not expected: lambert --model" bake --scene "$scene" --model lambert --out "$tmp/cache"
expect_bad "no such file" bake --scene "$tmp/none.json" --out "$tmp/cache"

# --- bake --max-error: the baker chooses the table; its headline error is the
# validated lookup error (bake, info --json, sample), the node-only error a secondary field
"$G" bake --model specular:alpha=100 --law g --max-error 1e-3 -o "$tmp/to_error.exr" --json >"$tmp/to_error.json" \
  && ok || fail "bake --max-error"
[ "$(json_field "$tmp/to_error.json" "d['tables'][0]['lookup_error'] <= 1e-3 and d['tables'][0]['node_error'] <= d['tables'][0]['lookup_error'] and d['tables'][0]['value_bytes'] > 0")" = "True" ] \
  && ok || fail "bake --max-error JSON: $(cat "$tmp/to_error.json")"
"$G" info "$tmp/to_error.exr" --json >"$tmp/to_error_info.json" && ok || fail "info of a --max-error table"
[ "$(json_field "$tmp/to_error_info.json" "d['error'] <= 1e-3 and d['error'] >= d['node_error'] and d['frame']=='lobe' and d['interpolation']=='catmull-rom' and d['format_version']==6 and d['target_error']==1e-3 and d['value_bytes']==4*d['entries'] and d['validation_points'] >= 2000")" = "True" ] \
  && ok || fail "info --json of a --max-error table: $(cat "$tmp/to_error_info.json")"
"$G" info "$tmp/to_error.exr" | grep -q "^  error  .*lookup error" && ok || fail "info headline is not the lookup error"
[ "$(json_field <("$G" sample "$tmp/to_error.exr" --theta-i 60 --theta-j 45 --phi 30 --json) "d['error']==$(json_field "$tmp/to_error_info.json" "d['error']")")" = "True" ] \
  && ok || fail "sample does not report the table's lookup error"
[ "$(json_field <("$G" bake --model specular:alpha=100 --law g --max-error 1e-3 -o "$tmp/to_error.exr" --json) "d['tables'][0]['status']")" = "reused" ] \
  && ok || fail "bake --max-error not reused"
expect_bad "--max-error 0 is not allowed" bake --model specular:alpha=8 --law h --max-error 0 -o "$tmp/bad_e.exr"
expect_bad "--max-error -1 is not allowed" bake --model specular:alpha=8 --law h --max-error -1 -o "$tmp/bad_e.exr"
expect_bad "--max-error nan is not allowed" bake --model specular:alpha=8 --law h --max-error nan -o "$tmp/bad_e.exr"
expect_bad "below what a float table can hold" bake --model specular:alpha=8 --law h --max-error 1e-9 -o "$tmp/bad_e.exr"
expect_bad "below what a half table can hold" bake --model specular:alpha=8 --law h --max-error 1e-4 --encoding half -o "$tmp/bad_e.exr"
expect_bad "--res excludes --max-error" bake --model specular:alpha=8 --law h --res 9 --max-error 1e-4 -o "$tmp/bad_e.exr"
expect_bad "--res excludes --max-bytes" bake --model specular:alpha=8 --law h --res 9 --max-bytes 100000 -o "$tmp/bad_e.exr"
expect_bad "--max-bytes 8 is too small" bake --model specular:alpha=8 --law g --max-error 1e-3 --max-bytes 8 -o "$tmp/bad_e.exr"
expect_bad "cannot reach --max-error" bake --model specular:alpha=100 --law g --max-error 1e-6 --max-bytes 4096 -o "$tmp/bad_e.exr"
expect_bad "below what a unorm16 table can hold" bake --model specular:alpha=8 --law h --max-error 1e-5 --encoding unorm16 -o "$tmp/bad_e.exr"
# --best-effort: the most accurate table the search made, its stated error the miss
expect_bad "--best-effort needs --max-error" bake --model specular:alpha=8 --law h --res 9 --best-effort -o "$tmp/bad_e.exr"
"$G" bake --model specular:alpha=100 --law h --max-error 1e-6 --max-bytes 32 --best-effort -o "$tmp/best.exr" --quiet &&
  "$G" info "$tmp/best.exr" --json >"$tmp/best.json" &&
  [ "$(json_field "$tmp/best.json" "d['error'] > d['target_error'] == 1e-6 and d['value_bytes'] <= 32")" = True ] &&
  ok || fail "bake --best-effort: $(cat "$tmp/best.json" 2>/dev/null | head -c 300)"
# --fetches: a fetch budget per lookup; one fetch is the hardware filter, and its bound says so
expect_bad "--fetches 0 is not allowed" bake --model specular:alpha=8 --law h --max-error 1e-3 --fetches 0 -o "$tmp/bad_e.exr"
expect_bad "--fetches" bake --model specular:alpha=8 --law h --max-error 1e-3 --fetches 1.5 -o "$tmp/bad_e.exr"
expect_bad "--res excludes --fetches" bake --model specular:alpha=8 --law h --res 9 --fetches 1 -o "$tmp/bad_e.exr"

# bake by job: each subcommand takes only its own flags; the old spellings are aliases that bake
# the very same table (the files differ only in the stamped command line)
"$G" bake model specular:alpha=8 --law h --res 17 -o "$tmp/job_model.exr" --quiet >/dev/null && ok || fail "bake model"
"$G" bake --model specular:alpha=8 --law h --res 17 -o "$tmp/job_alias.exr" --quiet >/dev/null && ok || fail "bake --model alias"
[ "$("$G" info "$tmp/job_model.exr" --json | grep -v '"path"\|"command"')" = "$("$G" info "$tmp/job_alias.exr" --json | grep -v '"path"\|"command"')" ] \
  && ok || fail "bake model and its alias bake different tables"
"$G" bake model specular:alpha=8 --law h --max-error 1e-3 -o "$tmp/job_target.exr" --quiet >/dev/null && ok || fail "bake model --max-error"
expect_bad "not expected: 9x9x5 --res-g" bake model specular:alpha=8 --law g --res 9 --res-g 9x9x5 -o "$tmp/bad.exr"
expect_bad "not expected: 0/2 --shard" bake model specular:alpha=8 --law g --res 9 --shard 0/2 -o "$tmp/bad.exr"
expect_bad "--frame excludes --max-error" bake model specular:alpha=8 --law g --max-error 1e-3 --frame lobe -o "$tmp/bad.exr"
expect_bad "--tol excludes --max-error" bake model specular:alpha=8 --law g --max-error 1e-3 --tol 1e-6 -o "$tmp/bad.exr"
expect_bad "--max-bytes needs --max-error" bake model specular:alpha=8 --law h --max-bytes 1000 -o "$tmp/bad.exr"
expect_bad "not expected: 2 --max-bytes" bake preset dfg --model ggx --res 8 --max-bytes 2 -o "$tmp/bad.exr"
expect_bad "not expected: 9 --res" bake scene "$scene" --out "$tmp/cache" --res 9
expect_bad "bake needs a job" bake
expect_bad "within 1 texture fetch per lookup" bake --model specular:alpha=100 --law g --max-error 1e-5 --fetches 1 --max-bytes 4096 -o "$tmp/bad_e.exr"
expect_bad "no filtered path" sample "$tmp/dfg.exr" --roughness 0.5 --mu 0.5 --hardware-filter
"$G" bake --model specular:alpha=100 --law h --max-error 1e-3 --fetches 1 -o "$tmp/h1.exr" >/dev/null && ok || fail "bake --fetches 1"
"$G" info "$tmp/h1.exr" | grep -q "hardware filter (GL_LINEAR): 1 texture fetch per lookup" && ok || fail "info names the lookup"
[ "$(json_field <("$G" info "$tmp/h1.exr" --json) "d['filter']=='hardware' and d['fetches']==1 and d['target_fetches']==1")" = "True" ] \
  && ok || fail "info --json of a --fetches 1 table"
[ "$(json_field <("$G" sample "$tmp/h1.exr" --theta-j 60 --hardware-filter --json) "abs(d['value'] - 0.5) < 0.5 and d['bound_filter']=='hardware'")" = "True" ] \
  && ok || fail "sample --hardware-filter"
expect_bad "unknown encoding 'unorm8'; allowed: half, float, unorm16" bake --model specular:alpha=8 --law h --res 9 --encoding unorm8 -o "$tmp/bad_e.exr"
expect_bad "a preset table allows: half, float" bake --preset dfg --model ggx --res 8 --encoding unorm16 -o "$tmp/bad_e.exr"
[ ! -e "$tmp/bad_e.exr" ] && ok || fail "a refused --max-error bake left a file"
# unorm16 (the 16-bit encoding): 2 value bytes per entry, offset and scale in info --json
"$G" bake --model specular:alpha=8 --law h --res 33 --encoding unorm16 -o "$tmp/unorm16.exr" >/dev/null && ok || fail "bake --encoding unorm16"
[ "$(json_field <("$G" info "$tmp/unorm16.exr" --json) "(d['encoding'], d['value_bytes'], d['unorm16']['scale'] > 0)")" = "('unorm16', 66, True)" ] \
  && ok || fail "info --json of a unorm16 table: $("$G" info "$tmp/unorm16.exr" --json)"
# scenes honour --max-error (and it is in the cache key: a second run reuses everything)
"$G" bake --scene "$scene" --out "$tmp/err_cache" --max-error 1e-3 --json >"$tmp/err_scene.json" && ok || fail "scene --max-error"
[ "$(json_field "$tmp/err_scene.json" "all(t['lookup_error'] <= 1e-3 for t in d['tables']) and len(d['tables'])==6")" = "True" ] \
  && ok || fail "scene --max-error JSON: $(cat "$tmp/err_scene.json")"
[ "$(json_field <("$G" bake --scene "$scene" --out "$tmp/err_cache" --max-error 1e-3 --json) "all(t['status']=='reused' for t in d['tables'])")" = "True" ] \
  && ok || fail "scene --max-error not reused"
expect_bad "drop --res-g or --max-error" bake --scene "$scene" --out "$tmp/err_cache" --max-error 1e-3 --res-g 9
# tradeoff --schemes (docs/tradeoff.md part 1): refusals before any bake
expect_bad "--schemes measures fixed schemes" tradeoff --schemes --model specular:alpha=8 --law g --res 9x9x5
expect_bad "--repeats needs --schemes" tradeoff --model specular:alpha=8 --law g --repeats 2
expect_bad "--repeats 0 is not allowed" tradeoff --schemes --model specular:alpha=8 --law g --repeats 0 --quick

# --- one planner: a cache baked with non-default table options is what render and export-glsl
# reach with the same options (nothing baked again), and tables from the cache shade exactly as
# tables baked in memory
opts=(--res-g 5x5x3 --res-h 9 --tol 1e-6 --encoding half --max-evals 200000)
"$G" bake --scene "$scene" --out "$tmp/plan_cache" "${opts[@]}" --json >"$tmp/plan_bake.json" && ok || fail "planned bake"
[ "$(json_field "$tmp/plan_bake.json" "len(d['tables'])==6 and all(t['status']=='baked' for t in d['tables'])")" = "True" ] \
  && ok || fail "planned bake JSON: $(cat "$tmp/plan_bake.json")"
"$G" render --scene "$scene" --cache "$tmp/plan_cache" "${opts[@]}" -o "$tmp/cached.exr" --json >"$tmp/plan_render.json" \
  && ok || fail "render from the cache"
[ "$(json_field "$tmp/plan_render.json" "len(d['tables'])==6 and all(t['status']=='reused' for t in d['tables'])")" = "True" ] \
  && ok || fail "render baked again: $(cat "$tmp/plan_render.json")"
"$G" export-glsl --scene "$scene" --cache "$tmp/plan_cache" "${opts[@]}" --out "$tmp/plan_glsl" --json >"$tmp/plan_glsl.json" \
  && ok || fail "export-glsl from the cache"
[ "$(json_field "$tmp/plan_glsl.json" "len(d['tables'])==6 and all(t['status']=='reused' for t in d['tables'])")" = "True" ] \
  && ok || fail "export-glsl baked again: $(cat "$tmp/plan_glsl.json")"
[ "$(ls "$tmp/plan_cache" | wc -l)" -eq 6 ] && ok || fail "the cache grew: $(ls "$tmp/plan_cache")"
"$G" render --scene "$scene" "${opts[@]}" -o "$tmp/memory.exr" --quiet && ok || fail "render in memory"
cmp -s "$tmp/cached.exr" "$tmp/memory.exr" && ok || fail "cached and in-memory tables shade differently"
[ "$(json_field "$tmp/plan_glsl.json" "sorted((t['model'], t['law'], t['lookup_error'], t['node_error']) for t in d['textures']) == sorted((t['model'], t['law'], t['lookup_error'], t['node_error']) for t in $(cat "$tmp/plan_bake.json")['tables'])")" = "True" ] \
  && ok || fail "export-glsl's tables are not the baked ones"

# --- a table is self-describing: it reads without its model's data file
"$G" export-brdf --model minnaert:xi=0.5 --format tabulated --res 7x7x5 -o "$tmp/m.tab" >/dev/null && ok || fail "export-brdf"
"$G" bake --model "tabulated:file=$tmp/m.tab" --law h --res 5 --tol 1e-4 -o "$tmp/m.h.exr" >/dev/null && ok || fail "bake tabulated"
mv "$tmp/m.tab" "$tmp/m-moved.tab"
"$G" info "$tmp/m.h.exr" >/dev/null && ok || fail "info after the data file moved"
"$G" sample "$tmp/m.h.exr" --theta-j 30 >/dev/null && ok || fail "sample after the data file moved"
"$G" export-glsl "$tmp/m.h.exr" -o "$tmp/m.h.glsl" >/dev/null && ok || fail "export-glsl after the data file moved"

# --- a measured model is keyed by its file's bytes, not its path
bake_status() { json_field <("$G" bake --model "tabulated:file=$1" --law h --res 5 --tol 1e-4 -o "$tmp/k.h.exr" --json) "d['tables'][0]['status']"; }
"$G" export-brdf --model minnaert:xi=0.5 --format tabulated --res 7x7x5 -o "$tmp/k.tab" >/dev/null && ok || fail "export-brdf k.tab"
[ "$(bake_status "$tmp/k.tab")" = "baked" ] && ok || fail "first bake of k.tab"
[ "$(bake_status "$tmp/k.tab")" = "reused" ] && ok || fail "unchanged k.tab not reused"
[ "$(json_field <("$G" info "$tmp/k.h.exr" --json) "d['model_content'].startswith('fnv1a64:')")" = "True" ] \
  && ok || fail "info --json lacks model_content"
"$G" export-brdf --model minnaert:xi=1 --format tabulated --res 7x7x5 -o "$tmp/k.tab" >/dev/null && ok || fail "export-brdf over k.tab"
[ "$(bake_status "$tmp/k.tab")" = "baked" ] && ok || fail "new bytes in k.tab reused a stale table"
cp "$tmp/k.tab" "$tmp/k-copy.tab"
[ "$(bake_status "$tmp/k-copy.tab")" = "reused" ] && ok || fail "the same bytes at another path not reused"

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
