#!/usr/bin/env bash
# `ganzfeld export-glsl`: every exported snippet compiles with glslangValidator as
# GLSL 4.30 core and GLSL ES 3.00 fragment shaders, with texelFetch and with hardware filtering;
# the scene shader compiles; mismatched tables and bad input are refused with exit 2 and leave no
# output. Usage: glsl_export_test.sh PATH/TO/ganzfeld PATH/TO/glslangValidator
set -u
G="$1"
V="$2"
. "$(dirname "$0")/harness.sh"

# compile SNIPPET VERSION DEFINES CALL SAMPLER: wrap a snippet into a fragment shader and validate it
compile() {
  local snippet="$1" version="$2" defines="$3" call="$4" sampler="$5" name
  name="$tmp/$(basename "$snippet" .glsl)_${version// /_}_${defines:-plain}.frag"
  {
    echo "#version $version"
    [ -n "$defines" ] && echo "#define $defines"
    cat "$snippet"
    [ -n "$sampler" ] && echo "uniform highp $sampler tab;"
    echo "out vec4 color;"
    echo "void main() { color = vec4($call); }"
  } >"$name"
  if "$V" "$name" >"$tmp/validator.log" 2>&1; then ok; else fail "glslangValidator $name: $(cat "$tmp/validator.log")"; fi
}

# compile_table SNIPPET FUNCTION LAW: a table's snippet in both versions, with texelFetch and with
# hardware filtering, calling FUNCTION at one point (g: tab, i, j, n; h and a: tab, direction, n)
compile_table() {
  local snippet="$1" function="$2" law="$3" call sampler version defines
  if [ "$law" = g ]; then
    call="$function(tab, vec3(0.3, 0.0, 0.9), vec3(-0.2, 0.1, 0.9), vec3(0.0, 0.0, 1.0))" sampler=sampler3D
  else
    call="$function(tab, vec3(0.3, 0.0, 0.9), vec3(0.0, 0.0, 1.0))" sampler=sampler2D
  fi
  for version in "430 core" "300 es"; do
    for defines in "" GANZFELD_HARDWARE_FILTER; do compile "$snippet" "$version" "$defines" "$call" "$sampler"; done
  done
}

# --- one table of each law, float and half
"$G" bake --model specular:alpha=8 --law g --res 9x9x5 --tol 1e-6 -o "$tmp/g.exr" --quiet >/dev/null || fail "bake g"
"$G" bake --model asperity:alpha=4 --law h --res 17 --tol 1e-6 --encoding half -o "$tmp/h.exr" --quiet >/dev/null || fail "bake h"
"$G" bake --model minnaert:xi=0.5 --law a --res 17 --tol 1e-6 -o "$tmp/a.exr" --quiet >/dev/null || fail "bake a"
"$G" export-glsl "$tmp/g.exr" -o "$tmp/g.glsl" --json >"$tmp/g.json" && ok || fail "export g"
[ -s "$tmp/g.ktx2" ] && ok || fail "no g.ktx2"
python3 -c "import json; d=json.load(open('$tmp/g.json')); assert d['function']=='gz_specular_alpha_8_g' and d['sampler']=='sampler3D' and d['texture'].endswith('g.ktx2')" \
  && ok || fail "export JSON: $(cat "$tmp/g.json")"
"$G" export-glsl "$tmp/h.exr" -o "$tmp/h.glsl" --texture header --quiet && ok || fail "export h"
grep -q "static const uint16_t gz_asperity_alpha_4_h_texels\[17\]" "$tmp/h.h" && ok || fail "C header of a half table"
"$G" export-glsl "$tmp/a.exr" -o "$tmp/a.glsl" --texture none --quiet && ok || fail "export a"
[ ! -e "$tmp/a.ktx2" ] && [ ! -e "$tmp/a.h" ] && ok || fail "--texture none wrote a texture"
grep -q "made by: ganzfeld bake --model minnaert:xi=0.5 --law a" "$tmp/a.glsl" && ok || fail "command not in the GLSL comment"

compile_table "$tmp/g.glsl" gz_specular_alpha_8_g g
compile_table "$tmp/h.glsl" gz_asperity_alpha_4_h h
compile_table "$tmp/a.glsl" gz_minnaert_xi_0_5_a a
# Format version 2 (bake --max-error): lobe frame (sinh mappings) and Catmull–Rom, g and h.
"$G" bake --model specular:alpha=100 --law g --max-error 1e-2 -o "$tmp/g2.exr" --quiet >/dev/null || fail "bake g v2"
"$G" bake --model specular:alpha=100 --law h --max-error 1e-4 -o "$tmp/h2.exr" --quiet >/dev/null || fail "bake h v2"
"$G" export-glsl "$tmp/g2.exr" -o "$tmp/g2.glsl" --quiet && ok || fail "export g v2"
"$G" export-glsl "$tmp/h2.exr" -o "$tmp/h2.glsl" --quiet && ok || fail "export h v2"
grep -q "gz_lobe_coordinates(i, j, n, -1.0)" "$tmp/g2.glsl" && grep -q "gz_lookup3_catmull_rom" "$tmp/g2.glsl" \
  && ok || fail "v2 g snippet without the lobe frame or Catmull–Rom"
compile_table "$tmp/g2.glsl" gz_specular_alpha_100_g g
compile_table "$tmp/h2.glsl" gz_specular_alpha_100_h h
# Format version 4: the warped frame read with one hardware-filtered fetch (g), and a filtered h.
"$G" bake --model specular:alpha=100 --law g --res 9x17x7 --tol 1e-5 --frame warped --filter hardware -o "$tmp/g4.exr" \
  --quiet >/dev/null || fail "bake g v4"
"$G" bake --model ggx:roughness=0.3 --law g --res 9x17x7 --tol 1e-5 --frame warped -o "$tmp/g4x.exr" --quiet >/dev/null \
  || fail "bake ggx g v4"
"$G" export-glsl "$tmp/g4.exr" -o "$tmp/g4.glsl" --quiet && ok || fail "export g v4"
"$G" export-glsl "$tmp/g4x.exr" -o "$tmp/g4x.glsl" --quiet && ok || fail "export ggx g v4"
grep -q "gz_lookup3_filtered" "$tmp/g4.glsl" && grep -q "gz_warped_offset" "$tmp/g4.glsl" \
  && grep -q "gz_warped_beta(warp, 0.8" "$tmp/g4.glsl" \
  && grep -q "const vec3 gz_specular_alpha_100_g_warp\[9\]" "$tmp/g4.glsl" \
  && grep -q "// lookup: 1 texture fetch, hardware filtering" "$tmp/g4.glsl" && ok || fail "v4 g snippet: warp or filter missing"
grep -q "// lookup: 8 texture fetches (texelFetch" "$tmp/g4x.glsl" && ! grep -q "gz_warp_envelope(cs_j" "$tmp/g4x.glsl" \
  && ok || fail "v4 ggx snippet: lookup line or an envelope it should not have"
compile_table "$tmp/g4.glsl" gz_specular_alpha_100_g g
compile_table "$tmp/g4x.glsl" gz_ggx_alpha_0_09_f0_1_g2_height_correlated_g g
# Two snippets in one shader: the shared helpers are guarded.
cat "$tmp/g.glsl" "$tmp/h.glsl" >"$tmp/both.glsl"
compile "$tmp/both.glsl" "430 core" "" "gz_specular_alpha_8_g(tab, vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0))" sampler3D

# --- the scene shader (every law kind, closed-form Lambert, collimated f of every K&P lobe)
cat >"$tmp/scene.json" <<'EOF'
{
  "camera": {"width": 64, "height": 64, "eye": [0, 0, 8], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 30},
  "materials": {
    "a": {"lobes": [{"weight": 0.5, "model": "lambert", "color": [1, 1, 1]},
                    {"weight": 0.5, "model": "backscatter:alpha=2", "color": [1, 0.5, 0.2]}]},
    "b": {"lobes": [{"weight": 0.5, "model": "perfect-backscatter:alpha=2", "color": [1, 1, 1]},
                    {"weight": 0.5, "model": "asperity:alpha=2", "color": [1, 1, 1]}]},
    "unused": {"model": "specular:alpha=1000"}
  },
  "objects": [{"shape": "sphere", "center": [-1, 0, 0], "radius": 1, "material": "a"},
              {"shape": "sphere", "center": [1, 0, 0], "radius": 1, "material": "b"}],
  "lights": [{"type": "collimated", "direction": [1, 1, 1], "irradiance": [1, 1, 1]},
             {"type": "hemispherical", "pole": [0, 1, 0], "radiance": [0.5, 0.5, 0.5]},
             {"type": "ganzfeld", "radiance": [0.2, 0.2, 0.2]}]
}
EOF
"$G" export-glsl --scene "$tmp/scene.json" --out "$tmp/scene_out" --tol 1e-5 --texture header --json >"$tmp/scene.json.out" \
  && ok || fail "export --scene"
python3 - "$tmp/scene.json.out" "$tmp/scene_out" <<'EOF' && ok || fail "scene manifest"
import json, os, sys
d = json.load(open(sys.argv[1]))
samplers = sorted(t["sampler"] for t in d["textures"])
# Lambert has closed forms; the unused material has no tables; three lobes x (g, h) tables
assert len(samplers) == 6, samplers
assert not any("lambert" in s or "1000" in s for s in samplers), samplers
for t in d["textures"]:
    assert os.path.exists(os.path.join(sys.argv[2], t["file"])), t
    # each table's own snippet beside its texture, defining the function the manifest names
    snippet = open(os.path.join(sys.argv[2], t["glsl"])).read()
    assert "float %s(highp %s table," % (t["function"], t["type"]) in snippet, t
    assert "// ganzfeld table: law %s of " % t["law"] in snippet, t
m = json.load(open(os.path.join(sys.argv[2], "manifest.json")))
assert m["textures"] == d["textures"]
EOF
# A scene table's snippet compiles alone (ES 3.00, as js/ganzfeld-three binds it).
g_snippet=$(ls "$tmp"/scene_out/gz_tex_*_g.glsl | head -1)
compile "$g_snippet" "300 es" "" "$(sed -n 's/^float \(gz_[A-Za-z0-9_]*_g\)(.*/\1/p' "$g_snippet")(tab, vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0), vec3(0.0, 0.0, 1.0))" sampler3D
# The same scene with every table baked to an error (format version 2 tables).
"$G" export-glsl --scene "$tmp/scene.json" --out "$tmp/scene_v2" --max-error 1e-2 --texture none --quiet \
  && ok || fail "export --scene --max-error"
grep -q "gz_lookup3_catmull_rom" "$tmp/scene_v2/ganzfeld_scene.glsl" && ok || fail "scene v2 shader without Catmull–Rom"
# Tables baked in memory (no --cache) still say which command bakes them: six "made by" lines,
# each a bake of one of the scene's lobes to the requested error.
[ "$(grep -c '^// made by: ganzfeld bake --model [a-z-]*:[a-z]*=[0-9]* --law [gh] --max-error 0.01 ' \
  "$tmp/scene_v2/ganzfeld_scene.glsl")" = 6 ] && ok || fail "scene tables baked in memory lack their bake command"
for version in "430 core" "300 es"; do
  compile "$tmp/scene_out/ganzfeld_scene.glsl" "$version" "" "gz_scene_radiance(1, vec3(0.0, 0.0, 1.0), vec3(0.0, 0.6, 0.8)), 1.0" ""
  compile "$tmp/scene_v2/ganzfeld_scene.glsl" "$version" "" "gz_scene_radiance(1, vec3(0.0, 0.0, 1.0), vec3(0.0, 0.6, 0.8)), 1.0" ""
done

# --- refusals: exit 2, one line, no output
expect_bad "needs law g of 'specular:alpha=8'" export-glsl "$tmp/h.exr" -o "$tmp/x.glsl" --model specular:alpha=8 --law g
expect_bad "needs law g of 'asperity:alpha=2'" export-glsl "$tmp/h.exr" -o "$tmp/x.glsl" --model asperity:alpha=2 --law g
expect_bad "needs law h of 'asperity:alpha=5'" export-glsl "$tmp/h.exr" -o "$tmp/x.glsl" --model asperity:alpha=5 --law h
"$G" export-glsl "$tmp/h.exr" -o "$tmp/right.glsl" --model asperity:alpha=4 --law h --quiet && ok || fail "matching --model/--law refused"
expect_bad "allowed: ktx2, header, none" export-glsl "$tmp/g.exr" -o "$tmp/x.glsl" --texture png
expect_bad "must end in .glsl" export-glsl "$tmp/g.exr" -o "$tmp/x.txt"
expect_bad "either TABLE.exr" export-glsl -o "$tmp/x.glsl"
printf 'not an exr' >"$tmp/bad.exr"
expect_bad "bad.exr" export-glsl "$tmp/bad.exr" -o "$tmp/x.glsl"
[ ! -e "$tmp/x.glsl" ] && [ ! -e "$tmp/x.ktx2" ] && ok || fail "a refused export left output"

# --- every analytic model of the registry under every light field: a collimated beam, a sky and a
# Ganzfeld; the shader compiles. Anisotropic models: their sky and Ganzfeld terms would need a fourth
# table axis, so that export is refused (docs/shaders.md), and under the beam alone it is accepted;
# so for a model with a mirror delta (he-torrance: Model::mirror_reflectance), which no table holds.
one_model_scene() {  # one_model_scene SPEC LIGHTS > scene.json
  printf '{"camera": {"width": 8, "height": 8}, "materials": {"m": {"model": "%s", "color": [1, 1, 1]}},
  "objects": [{"shape": "sphere", "material": "m", "tangent": {"axis": [0, 1, 0], "along": "longitude"}}], "lights": [%s]}' "$1" "$2"
}
BEAM='{"type": "collimated", "direction": [0.3, 0.5, 0.8], "irradiance": [1, 1, 1]}'
ALL="$BEAM, {\"type\": \"hemispherical\", \"pole\": [0, 1, 0.2], \"radiance\": [1, 1, 1]}, {\"type\": \"ganzfeld\", \"radiance\": [1, 1, 1]}"
"$G" models --json | python3 -c "
import json, sys
for m in json.load(sys.stdin)['models']:
    if 'file=DATA' in m['example']: continue
    # The examples of Lafortune (Cx = Cy), Ashikhmin-Shirley (nu = nv) and Schlick (p = 1) are
    # isotropic instances of anisotropic models: their anisotropic forms.
    anisotropic = {'lafortune': ('Cy=-1,', 'Cy=-0.8,'), 'ashikhmin-shirley': ('nv=100', 'nv=10'), 'schlick': ('p=1', 'p=0.5')}
    old, new = anisotropic.get(m['name'], ('', ''))
    spec = m['example'].replace(old, new) if old else m['example']
    kind = 'mirror' if m['name'] == 'he-torrance' else 'iso' if m['isotropic'] else 'aniso'
    print(m['name'], spec, kind)" >"$tmp/analytic"
while read -r name spec kind; do
  if [ "$kind" = iso ]; then
    one_model_scene "$spec" "$ALL" >"$tmp/m_$name.json"
    "$G" export-glsl --scene "$tmp/m_$name.json" --out "$tmp/m_$name" --res-g 3x3x2 --res-h 3 --tol 1e-3 --texture none --quiet \
      && compile "$tmp/m_$name/ganzfeld_scene.glsl" "300 es" "" "gz_scene_radiance(0, vec3(0.0, 0.0, 1.0), vec3(0.0, 0.6, 0.8)), 1.0" "" \
      || fail "export-glsl --scene of $spec under every light field"
  else
    tangent=$([ "$kind" = aniso ] && echo ", vec3(1.0, 0.0, 0.0)")
    refusal=$([ "$kind" = aniso ] && echo "is anisotropic: its sky and Ganzfeld terms have no tables" || echo "has a mirror delta besides f")
    one_model_scene "$spec" "$BEAM" >"$tmp/m_$name.json"
    "$G" export-glsl --scene "$tmp/m_$name.json" --out "$tmp/m_$name" --texture none --quiet \
      && compile "$tmp/m_$name/ganzfeld_scene.glsl" "300 es" "" "gz_scene_radiance(0, vec3(0.0, 0.0, 1.0), vec3(0.0, 0.6, 0.8)$tangent), 1.0" "" \
      || fail "export-glsl --scene of $spec under a beam"
    one_model_scene "$spec" "$ALL" >"$tmp/m_${name}_sky.json"
    expect_bad "$refusal" export-glsl --scene "$tmp/m_${name}_sky.json" --out "$tmp/m_${name}_sky" --tol 1e-3
    [ ! -e "$tmp/m_${name}_sky" ] && ok || fail "a refused scene export left output"
  fi
done <"$tmp/analytic"
[ "$(wc -l <"$tmp/analytic")" -ge 26 ] && ok || fail "fewer analytic models than registered: $(cat "$tmp/analytic")"
# A measured lobe under a beam has no GLSL f: refused by name, naming the models that have one.
"$G" export-brdf --model lambert --format tabulated --res 3x3x3 -o "$tmp/lambert.tab" >/dev/null || fail "export-brdf"
one_model_scene "tabulated:file=$tmp/lambert.tab" "$BEAM" >"$tmp/measured.json"
expect_bad "the viewer asks the service for it); available: the analytic models (lambert, minnaert" export-glsl --scene "$tmp/measured.json" --out "$tmp/measured_out"
[ ! -e "$tmp/measured_out" ] && ok || fail "a refused scene export left output"

echo "glsl_export_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
