#!/usr/bin/env bash
# The viewer in a real browser (issue #17): Debian's chromium-headless-shell, WebGL2 through
# SwiftShader, loads the page of a running `ganzfeld serve` in its test mode (one sphere of the
# K&P panel rendered into a float framebuffer, the pixels written into <pre id="result">), and
# tests/viewer_compare.cpp holds them against `ganzfeld render`'s image of the same scene, shaded
# from the same cache: the beam, the sky and the Ganzfeld, a mixture, a moved light, and a
# changed parameter that must change the image.
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
for _ in $(seq 100); do grep -q "listening on" "$tmp/log" && break; sleep 0.1; done
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

# What is compared must be able to differ: another light direction, another parameter.
check beam "model=$(uri "$SPEC")&light=collimated&dir=-0.3,0.6,0.74" page_beam_moved --expect-mismatch
check beam "model=specular:alpha=20&light=collimated&dir=0.3,0.6,0.74" page_alpha20 --expect-mismatch
reference beam20 specular:alpha=20 "{\"type\": \"collimated\", \"direction\": [0.3, 0.6, 0.74], \"irradiance\": [$PI08, $PI08, $PI08]}" 0.1
"$COMPARE" "$tmp/beam20.exr" "$tmp/page_alpha20.html" && ok || fail "alpha=20 page vs its own render"

# The interactive page comes up with its panels for model A and B (no test mode).
load interactive "model=$(uri "$SPEC")&model_b=$(uri minnaert:xi=1)"
grep -q '"ready":true,"rows":\["specular:alpha=8","minnaert:xi=1"\]' "$tmp/interactive.html" && ok \
  || fail "interactive page: $(grep -o '<pre id="result">.*</pre>' "$tmp/interactive.html"; grep -o 'class="error">[^<]*' "$tmp/interactive.html")"

# A bad model in the URL: the page reports the service's one-line error.
page bad "model=nosuchmodel&light=sky&dir=0,1,0"
grep -q '"error":"400 .*nosuchmodel' "$tmp/bad.html" && ok || fail "bad model: $(grep -o '<pre id="result">.*</pre>' "$tmp/bad.html")"

[ -n "${KEEP:-}" ] && cp -r "$tmp" "$KEEP"
echo "viewer_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
