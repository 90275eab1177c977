#!/usr/bin/env bash
# The viewer in a real browser: Debian's chromium-headless-shell, WebGL2 through
# SwiftShader, loads the page of a running `ganzfeld serve` in its test mode (one sphere of the
# K&P panel rendered into a float framebuffer, the pixels written into <pre id="result">), and
# tests/viewer_compare.cpp holds them against `ganzfeld render`'s image of the same scene, shaded
# from the same cache: the beam, the sky and the Ganzfeld, a mixture, GGX's sky (no GLSL f), a
# moved light and a changed parameter that must change the image; the interactive page, its
# numbers at the cursor, and the page's own errors (bad model, no WebGL).
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

"$G" serve --cache "$tmp/cache" --port 0 2>"$tmp/log" &
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
page() { load "$1" "test=1&size=$SIZE&$2"; }  # the test mode: one sphere, its pixels as JSON
# reference NAME MODEL LIGHT_JSON BACKGROUND: `ganzfeld render` of the figure's sphere
# (rasterizer/figure.cpp: eye (0, 0, 6), fov 25°) under one light, from the server's cache.
reference() {
  cat >"$tmp/$1.json" <<EOF
{"camera": {"width": $SIZE, "height": $SIZE, "eye": [0, 0, 6], "target": [0, 0, 0], "up": [0, 1, 0],
            "fov_deg": 25, "background": [$4, $4, $4]},
 "materials": {"m": {"model": "$2", "color": [1, 1, 1]}},
 "objects": [{"shape": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}],
 "lights": [$3]}
EOF
  "$G" render --scene "$tmp/$1.json" --cache "$tmp/cache" --quiet -o "$tmp/$1.exr" || fail "render $1"
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

# A mixture (f of each lobe summed in GLSL; g from the mixture's own table).
MIX="0.7*minnaert:xi=1 + 0.3*backscatter:alpha=2"
reference mix_beam "$MIX" "{\"type\": \"collimated\", \"direction\": [-0.5, 0.2, 0.8], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
check mix_beam "model=$(uri "$MIX")&light=collimated&dir=-0.5,0.2,0.8" page_mix_beam

# A model without a GLSL f (GGX): its sky still comes from its table; its beam is refused by name.
reference ggx_sky ggx:alpha=0.3 '{"type": "hemispherical", "pole": [0.2, 0.9, 0.4], "radiance": [0.8, 0.8, 0.8]}' 0.1
check ggx_sky "model=$(uri ggx:alpha=0.3)&light=sky&dir=0.2,0.9,0.4" page_ggx_sky
page ggx_beam "model=$(uri ggx:alpha=0.3)&light=collimated&dir=0,0,1"
grep -q '"error":"400 .*no GLSL form of f' "$tmp/ggx_beam.html" && ok || fail "ggx beam: $(grep -o '<pre id="result">.*</pre>' "$tmp/ggx_beam.html")"

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
if python3 "$(dirname "$0")/viewer_drive.py" "$BROWSER" "http://127.0.0.1:$port/?model=$(uri "$SPEC")&dir=0.3,0.6,0.74" \
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
load interactive "model=$(uri "$SPEC")&model_b=$(uri minnaert:xi=1)&dir=0.3,0.6,0.74&pole=0.2,0.9,0.4&probe=0.6,0.4"
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

# A bad model in the URL: the page reports the service's one-line error.
page bad "model=nosuchmodel&light=sky&dir=0,1,0"
grep -q '"error":"400 .*nosuchmodel' "$tmp/bad.html" && ok || fail "bad model: $(grep -o '<pre id="result">.*</pre>' "$tmp/bad.html")"

[ -n "${KEEP:-}" ] && cp -r "$tmp" "$KEEP"
echo "viewer_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
