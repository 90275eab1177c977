#!/usr/bin/env bash
# The viewer in a real browser: Debian's chromium-headless-shell, WebGL2 through
# SwiftShader, loads the page of a running `ganzfeld serve` in its test mode (one sphere of the
# K&P panel rendered into a float framebuffer, the pixels written into <pre id="result">), and
# tests/viewer_compare.cpp holds them against `ganzfeld render`'s image of the same scene, shaded
# from the same cache: the beam, the sky and the Ganzfeld, a mixture, GGX, He-Torrance's sky and
# Ganzfeld with its mirror delta, an anisotropic model
# brushed both ways (its sky by the service's cubature), a measured file of --data (its beam from
# the service, as shown within 2 LSB), a moved light and a changed parameter that must change the
# image; the interactive page, its numbers at the cursor, the walk over every registered model
# (tests/viewer_walk.py: no empty panel), and the page's own errors (bad model, bad colour or
# azimuth, no WebGL).
# Usage: viewer_test.sh PATH/TO/ganzfeld PATH/TO/viewer_compare
set -u
G="$1"
COMPARE="$2"
. "$(dirname "$0")/harness.sh"
# The real binary in the package's lib directory: the wrapper on PATH misparses the flags.
BROWSER=$(dpkg -L chromium-headless-shell 2>/dev/null | grep -m1 '^/usr/lib/.*/chromium-headless-shell$')
if [ -z "$BROWSER" ] || [ ! -x "$BROWSER" ]; then
  echo "FAIL: chromium-headless-shell is not installed (a test dependency: scripts/install-deps installs it)"
  exit 1
fi
SIZE=64  # pixels per side: the sphere covers ~1,700 of them (viewer_compare.cpp: kMinCompared)
# Tables: the scene defaults (lookup error 1e-3 at one hardware-filtered fetch, best effort: uploaded
# with LINEAR filtering) for the first model; small fixed tables for the rest,
# on both sides (the page's table_res and table_tol, render's --res-g, --res-h and --tol), since the
# page and render are compared on the same cache entries whatever their resolution, and a search
# per model would take most of the test's time on a shared 2-core machine.
SMALL_G=12x12x6 SMALL_H=32 SMALL_TOL=1e-5
SMALL_PAGE="table_res=$SMALL_G,$SMALL_H&table_tol=$SMALL_TOL"
SMALL_RENDER="--res-g $SMALL_G --res-h $SMALL_H --tol $SMALL_TOL"
TABLES_PAGE="" TABLES_RENDER=""  # the scene defaults, until the first model's checks are done

# --data: measured files the service lists by name (export-brdf writes MERL and tabulated files
# from a model; no measured file can be downloaded here), a first-surface table, and a file it skips.
mkdir -p "$tmp/data"
"$G" export-brdf --model cook-torrance --format merl -o "$tmp/data/cook.binary" >/dev/null || fail "export-brdf merl"
"$G" export-brdf --model "0.6*minnaert:xi=1 + 0.4*backscatter:alpha=4" --format tabulated --res 19x19x19 \
  -o "$tmp/data/moon.tab" >/dev/null || fail "export-brdf tabulated"
printf 'ganzfeld-beard-maxwell-first-surface 1\ntheta_N: 0 10 20 40 90\nrho_fs: 2 1.2 0.4 0.05 0\n' >"$tmp/data/paint.fs"
echo "not a BRDF" >"$tmp/data/notes.txt"
"$G" serve --cache "$tmp/cache" --data "$tmp/data" --port 0 2>"$tmp/log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null; wait $pid 2>/dev/null; rm -rf "$tmp"' EXIT
for _ in $(seq 100); do grep -qs "listening on" "$tmp/log" && break; sleep 0.1; done
port=$(sed -nE 's|.*listening on http://127\.0\.0\.1:([0-9]+)/.*|\1|p' "$tmp/log")
[ -n "$port" ] || { echo "FAIL: no listening line: $(cat "$tmp/log")"; exit 1; }

# load NAME QUERY: the DOM of /?QUERY after its asynchronous work, in $tmp/NAME.html. The browser
# exits 0 even when the page failed: the page's own result is what is checked.
load() {
  "$BROWSER" --no-sandbox --headless --use-angle=swiftshader --enable-unsafe-swiftshader --virtual-time-budget=60000 \
    --user-data-dir="$tmp/profile" --dump-dom "http://127.0.0.1:$port/?$2" >"$tmp/$1.html" 2>"$tmp/$1.browser.log"
}
page() { load "$1" "test=1&size=$SIZE${TABLES_PAGE:+&$TABLES_PAGE}&$2"; }  # the test mode: one sphere, its pixels as JSON
# reference NAME MODEL LIGHT_JSON BACKGROUND: `ganzfeld render` of the figure's sphere
# (rasterizer/figure.cpp: eye (0, 0, 6), fov 25°) under one light, from the server's cache, with
# the tables the page asks for.
reference() {
  cat >"$tmp/$1.json" <<EOF
{"camera": {"width": $SIZE, "height": $SIZE, "eye": [0, 0, 6], "target": [0, 0, 0], "up": [0, 1, 0],
            "fov_deg": 25, "background": [$4, $4, $4]},
 "materials": {"m": {"model": "$2", "color": [1, 1, 1]}},
 "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
 "lights": [$3]}
EOF
  "$G" render --scene "$tmp/$1.json" --cache "$tmp/cache" --quiet $TABLES_RENDER -o "$tmp/$1.exr" || fail "render $1"
}
# check NAME QUERY [--expect-mismatch]: the page of QUERY against reference NAME.
check() {
  page "$3" "$2"
  "$COMPARE" "$tmp/$1.exr" "$tmp/$3.html" ${4:-} && ok || fail "$3 vs $1 ($2): $(head -c 300 "$tmp/$3.html")"
}
uri() { python3 -c "import sys, urllib.parse; print(urllib.parse.quote(sys.argv[1], safe=''))" "$1"; }

# f.n = H0 (i.n) f under the beam (H0 = pi 0.8), g under a tilted sky pole, h in a Ganzfeld.
PI08=2.5132741228718345  # pi x 0.8: rasterizer/figure.h kFieldRadiance under a beam
SPEC=specular:alpha=8
reference beam "$SPEC" "{\"type\": \"collimated\", \"direction\": [0.3, 0.6, 0.74], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
reference sky "$SPEC" '{"type": "hemispherical", "pole": [0.2, 0.9, 0.4], "radiance": [0.8, 0.8, 0.8]}' 0.1
reference ganzfeld "$SPEC" '{"type": "ganzfeld", "radiance": [0.8, 0.8, 0.8]}' 0.8
check beam "model=$(uri "$SPEC")&light=collimated&dir=0.3,0.6,0.74" page_beam
check sky "model=$(uri "$SPEC")&light=sky&dir=0.2,0.9,0.4" page_sky
check ganzfeld "model=$(uri "$SPEC")&light=ganzfeld" page_ganzfeld
grep -q '"filters":\["hardware","hardware"\]' "$tmp/page_sky.html" && ok || fail "the default tables are not hardware-filtered"
TABLES_PAGE=$SMALL_PAGE TABLES_RENDER=$SMALL_RENDER

# A mixture (f of each lobe summed in GLSL; g from the mixture's own table).
MIX="0.7*minnaert:xi=1 + 0.3*backscatter:alpha=2"
reference mix_beam "$MIX" "{\"type\": \"collimated\", \"direction\": [-0.5, 0.2, 0.8], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
check mix_beam "model=$(uri "$MIX")&light=collimated&dir=-0.5,0.2,0.8" page_mix_beam

# GGX: its beam from its GLSL f, its sky from its table.
reference ggx_sky ggx:alpha=0.3 '{"type": "hemispherical", "pole": [0.2, 0.9, 0.4], "radiance": [0.8, 0.8, 0.8]}' 0.1
check ggx_sky "model=$(uri ggx:alpha=0.3)&light=sky&dir=0.2,0.9,0.4" page_ggx_sky
reference ggx_beam ggx:alpha=0.3 "{\"type\": \"collimated\", \"direction\": [0.3, 0.6, 0.74], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
check ggx_beam "model=$(uri ggx:alpha=0.3)&light=collimated&dir=0.3,0.6,0.74" page_ggx_beam

# He-Torrance: its mirror delta, which no table holds, added to the sky (where the mirror direction
# of j sees it) and to the Ganzfeld on both sides (the page's gz_mirror_<spec>, render's shading).
HT=he-torrance:sigma0=0.02
reference ht_sky "$HT" '{"type": "hemispherical", "pole": [0.2, 0.9, 0.4], "radiance": [0.8, 0.8, 0.8]}' 0.1
check ht_sky "model=$(uri "$HT")&light=sky&dir=0.2,0.9,0.4" page_ht_sky
reference ht_ganzfeld "$HT" '{"type": "ganzfeld", "radiance": [0.8, 0.8, 0.8]}' 0.8
check ht_ganzfeld "model=$(uri "$HT")&light=ganzfeld" page_ht_ganzfeld

# Anisotropic Ward, brushed along the latitudes about +y (the default of scenes and the page) and
# along the meridians: the beam from its GLSL f in the sphere's tangent frame; the sky from the
# service's cubature per pixel (no tables), against `render`'s cubature per pixel.
ANISO=ward-aniso:rho_d=0.1,rho_s=0.33,alpha_x=0.05,alpha_y=0.3
reference aniso_lat "$ANISO" "{\"type\": \"collimated\", \"direction\": [0.3, 0.6, 0.74], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
check aniso_lat "model=$(uri "$ANISO")&light=collimated&dir=0.3,0.6,0.74" page_aniso_lat
sed 's/"material": "m"}/"material": "m", "tangent": {"along": "longitude"}}/' "$tmp/aniso_lat.json" >"$tmp/aniso_lon.json"
"$G" render --scene "$tmp/aniso_lon.json" --cache "$tmp/cache" --quiet -o "$tmp/aniso_lon.exr" || fail "render aniso_lon"
check aniso_lon "model=$(uri "$ANISO")&light=collimated&dir=0.3,0.6,0.74&along=longitude" page_aniso_lon
"$COMPARE" "$tmp/aniso_lat.exr" "$tmp/page_aniso_lon.html" --expect-mismatch && ok || fail "the tangent does not turn the highlight"
SMALL=$SIZE; SIZE=48  # a cubature per pixel on both sides: a smaller sphere
reference aniso_sky "$ANISO" '{"type": "hemispherical", "pole": [0.2, 0.9, 0.4], "radiance": [0.8, 0.8, 0.8]}' 0.1
page page_aniso_sky "model=$(uri "$ANISO")&light=sky&dir=0.2,0.9,0.4&service_tol=1e-7"
# render integrates to 1e-6 (cli/cmd_render.cpp, kDirectTol), the service to 1e-7: their sum, 10x.
"$COMPARE" "$tmp/aniso_sky.exr" "$tmp/page_aniso_sky.html" --absolute 1.1e-5 && ok || fail "anisotropic sky vs render"
grep -q '"source":"service"' "$tmp/page_aniso_sky.html" && ok || fail "anisotropic sky not from the service"
SIZE=$SMALL

# A measured file of --data, by name: its beam from the service (no GLSL f), shown as render draws it.
DATA_SPEC=merl:file=cook.binary
cat >"$tmp/merl_beam.json" <<EOF
{"camera": {"width": $SIZE, "height": $SIZE, "eye": [0, 0, 6], "target": [0, 0, 0], "up": [0, 1, 0],
            "fov_deg": 25, "background": [0.1, 0.1, 0.1]},
 "materials": {"m": {"model": "merl:file=$tmp/data/cook.binary", "color": [1, 1, 1]}},
 "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
 "lights": [{"type": "collimated", "direction": [0.3, 0.6, 0.74], "irradiance": [$PI08, $PI08, $PI08]}]}
EOF
"$G" render --scene "$tmp/merl_beam.json" --cache "$tmp/cache" --quiet -o "$tmp/merl_beam.exr" || fail "render merl"
# Small g and h tables: the page loads them with f, and only the beam is compared.
TABLES_PAGE="table_res=5x5x3,9&table_tol=1e-3" page page_merl_beam "model=$(uri "$DATA_SPEC")&light=collimated&dir=0.3,0.6,0.74&display=1"
if "$COMPARE" "$tmp/merl_beam.exr" "$tmp/page_merl_beam.html" --srgb-lsb 2 >"$tmp/merl_lsb.txt"; then ok; else fail "measured beam vs render: $(cat "$tmp/merl_lsb.txt")"; fi
[ -n "${LSB_REPORT:-}" ] && cp "$tmp/merl_lsb.txt" "$LSB_REPORT"
"$COMPARE" "$tmp/merl_beam.exr" "$tmp/page_merl_beam.html" && ok || fail "measured beam vs render (linear)"
grep -q '"source":"service"' "$tmp/page_merl_beam.html" && ok || fail "measured beam not from the service"
page page_missing "model=$(uri merl:file=nosuch.binary)&light=collimated&dir=0,0,1"
grep -q '"error":"404 .*no data file .nosuch.binary' "$tmp/page_missing.html" && ok || fail "a name not in --data: $(grep -o '<pre id="result">.*</pre>' "$tmp/page_missing.html")"

# Without WebGL the page says so (the comparisons above rely on its saying so, not on a blank image).
"$BROWSER" --no-sandbox --headless --disable-webgl --virtual-time-budget=60000 --user-data-dir="$tmp/profile" \
  --dump-dom "http://127.0.0.1:$port/?test=1&size=$SIZE&model=lambert&light=ganzfeld" >"$tmp/nowebgl.html" 2>/dev/null
grep -q '"error":"no WebGL2 context"' "$tmp/nowebgl.html" && ok || fail "no WebGL: $(grep -o '<pre id="result">.*</pre>' "$tmp/nowebgl.html")"

# What is compared must be able to differ: another light direction, another parameter.
check beam "model=$(uri "$SPEC")&light=collimated&dir=-0.3,0.6,0.74" page_beam_moved --expect-mismatch
check beam "model=specular:alpha=20&light=collimated&dir=0.3,0.6,0.74" page_alpha20 --expect-mismatch
reference beam20 specular:alpha=20 "{\"type\": \"collimated\", \"direction\": [0.3, 0.6, 0.74], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
"$COMPARE" "$tmp/beam20.exr" "$tmp/page_alpha20.html" && ok || fail "alpha=20 page vs its own render"

# A slider dragged with the mouse (tests/viewer_drive.py, DevTools protocol): the spec follows,
# the row is rebuilt from the new tables, and its beam sphere is `ganzfeld render`'s of the new spec.
if python3 "$(dirname "$0")/viewer_drive.py" "$BROWSER" "http://127.0.0.1:$port/?model=$(uri "$SPEC")&dir=0.3,0.6,0.74&$SMALL_PAGE" \
     "$tmp/page_drag.html" "$SIZE" >"$tmp/drive.json" 2>"$tmp/drive.err"; then
  dragged=$(json_field "$tmp/drive.json" "d['after']")
  [ "$(json_field "$tmp/drive.json" "d['before']")" = "$SPEC" ] && [ "$dragged" != "$SPEC" ] && ok || fail "drag: $(cat "$tmp/drive.json")"
  reference drag "$dragged" "{\"type\": \"collimated\", \"direction\": [0.3, 0.6, 0.74], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
  "$COMPARE" "$tmp/drag.exr" "$tmp/page_drag.html" && ok || fail "dragged page vs render of $dragged"
  "$COMPARE" "$tmp/beam.exr" "$tmp/page_drag.html" --expect-mismatch && ok || fail "dragging did not change the image"
else
  fail "viewer_drive.py: $(tail -3 "$tmp/drive.err")"
fi

# The interactive page comes up with its panels for model A and B (no test mode), and the numbers
# under a probed cursor are f, g, h, a, r at that point's angles: the angles computed here
# apart from the page (the figure's camera and sphere), the values those of `ganzfeld eval`.
load interactive "model=$(uri "$SPEC")&model_b=$(uri minnaert:xi=1)&dir=0.3,0.6,0.74&pole=0.2,0.9,0.4&probe=0.6,0.4&$SMALL_PAGE"
grep -q '"ready":true,"rows":\["specular:alpha=8","minnaert:xi=1"\]' "$tmp/interactive.html" && ok \
  || fail "interactive page: $(grep -o '<pre id="result">.*</pre>' "$tmp/interactive.html"; grep -o 'class="error">[^<]*' "$tmp/interactive.html")"
python3 - "$tmp/interactive.html" "$G" "$SPEC" <<'PY' && ok || fail "numbers at the cursor"
import json, math, re, subprocess, sys
dom, ganzfeld, spec = sys.argv[1], sys.argv[2], sys.argv[3]
text = re.search(r'<div id="numbers">(.*?)</div>', open(dom, encoding='utf-8').read(), re.S).group(1)
unit = lambda v: [x / math.sqrt(sum(y * y for y in v)) for x in v]
dot = lambda a, b: sum(x * y for x, y in zip(a, b))
t = math.tan(math.radians(12.5))                          # the figure's 25° field of view
d = unit([(2 * 0.6 - 1) * t, (1 - 2 * 0.4) * t, -1])      # probe (0.6, 0.4), eye (0, 0, 6)
b = dot([0, 0, 6], d)
s = -b - math.sqrt(b * b - 35)                            # |eye|^2 - 1 = 35
n = unit([s * d[0], s * d[1], 6 + s * d[2]])
j = [-x for x in d]
def azimuth(a):
    ta = [x - dot(a, n) * y for x, y in zip(a, n)]
    tj = [x - dot(j, n) * y for x, y in zip(j, n)]
    return math.degrees(math.acos(dot(ta, tj) / math.sqrt(dot(ta, ta) * dot(tj, tj))))
beam, pole = unit([0.3, 0.6, 0.74]), unit([0.2, 0.9, 0.4])
angles = {'f': (math.degrees(math.acos(dot(beam, n))), math.degrees(math.acos(dot(j, n))), azimuth(beam)),
          'g': (math.degrees(math.acos(dot(pole, n))), math.degrees(math.acos(dot(j, n))), azimuth(pole))}
for law, (ti, tj, phi) in angles.items():
    line = re.search('^%s = (\\S+) .*θi ([0-9.]+)°.*θj ([0-9.]+)°, φ ([0-9.]+)°' % law, text, re.M)
    assert line, 'no line for %s in %r' % (law, text)
    shown = [float(x) for x in line.groups()[1:]]
    assert all(abs(x - y) <= 0.005 + 1e-9 for x, y in zip(shown, (ti, tj, phi))), (law, shown, (ti, tj, phi))
    cli = json.loads(subprocess.run([ganzfeld, 'eval', '--model', spec, '--law', law, '--theta-i', line.group(2),
                                     '--theta-j', line.group(3), '--phi', line.group(4), '--tol', '1e-6', '--json'],
                                    capture_output=True, text=True, check=True).stdout)
    assert '%.6g' % cli['value'] == '%.6g' % float(line.group(1)), (law, cli['value'], line.group(1))
one_angle = {'h': ('--theta-j', 'θj', angles['f'][1]), 'a': ('--theta-i', 'θi', angles['f'][0]), 'r': None}
for law, angle in one_angle.items():
    line = re.search('^%s = (\\S+) ± ' % law + ('.*%s ([0-9.]+)°' % angle[1] if angle else ''), text, re.M)
    assert line, 'no line for %s in %r' % (law, text)
    if angle: assert abs(float(line.group(2)) - angle[2]) <= 0.005 + 1e-9, (law, line.group(2), angle[2])
    command = [ganzfeld, 'eval', '--model', spec, '--law', law, '--tol', '1e-6', '--json'] + ([angle[0], line.group(2)] if angle else [])
    cli = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)
    assert '%.6g' % cli['value'] == '%.6g' % float(line.group(1)), (law, cli['value'], line.group(1))
PY

# A bad model in the URL: the page reports the service's one-line error; so for a colour or an
# azimuth out of range, the page's own.
page bad "model=nosuchmodel&light=sky&dir=0,1,0"
grep -q '"error":"400 .*nosuchmodel' "$tmp/bad.html" && ok || fail "bad model: $(grep -o '<pre id="result">.*</pre>' "$tmp/bad.html")"
page bad_color "model=lambert&light=collimated&dir=0,0,1&color_a=2,0,0"
grep -q '"error":"color_a=2,0,0 is out of range; allowed: R,G,B, three numbers in \[0, 1\]"' "$tmp/bad_color.html" && ok \
  || fail "bad colour: $(grep -o '<pre id="result">.*</pre>' "$tmp/bad_color.html")"
page bad_phi "model=lambert&light=collimated&dir=0,0,1&phi=400"
grep -q '"error":"phi=400 is out of range; allowed: an azimuth in \[0, 360\] degrees"' "$tmp/bad_phi.html" && ok \
  || fail "bad azimuth: $(grep -o '<pre id="result">.*</pre>' "$tmp/bad_phi.html")"

# Every registered model and every file of --data through the interactive page, one browser for
# all, small tables and spheres: no panel may be empty (tests/viewer_walk.py).
WALK="model=lambert&lobe=16&table_res=5x5x3,9&table_tol=1e-3&service_size=24&service_tol=1e-3"
if (cd "$(dirname "$0")" && python3 viewer_walk.py "$BROWSER" "http://127.0.0.1:$port/?$WALK") >"$tmp/walk.json" 2>"$tmp/walk.err"; then
  ok
else
  fail "viewer walk: $(tail -1 "$tmp/walk.json") $(grep -v '"lobe": true, "polar": true, "collimated": true, "sky": true, "ganzfeld": true' "$tmp/walk.json" | head -5) $(tail -3 "$tmp/walk.err")"
fi
[ -n "${WALK_REPORT:-}" ] && cp "$tmp/walk.json" "$WALK_REPORT"


[ -n "${KEEP:-}" ] && cp -r "$tmp" "$KEEP"
echo "viewer_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
