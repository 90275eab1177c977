#!/usr/bin/env bash
# js/ganzfeld-three inside three.js in a real browser: Debian's chromium-headless-shell, WebGL2
# through SwiftShader, on pages served from a temporary root (python3 -m http.server: the
# repository's js/ and examples/, and the tables under /t/).
#   1. The example scene (examples/three/scene.js at SIZE) as a ganzfeld scene file
#      (js/ganzfeld-three/bin/scene-file.js), its tables baked and exported by `export-glsl --scene`
#      to MAX_ERROR, and `ganzfeld render` of it from the same cache.
#   2. Pixels: the example page (test mode, diffuse 'lambert', the sky, ground and ambient light
#      only) against render's PNG: >= 99% of the covered pixels within 2 LSB in every channel, the
#      rest listed (threejs_compare.cpp). Stock three.js must fail that comparison (the module
#      changes the picture); the whole scene with the sun, and the default diffuse mode, are
#      compared and printed, not held (docs/three.md, "What differs").
#   3. Lookups: the module's tables and GLSL chunk evaluated on the GPU at 1024 seeded points per
#      table (js/ganzfeld-three/test/browser/lookup.js) against tables::sample, and a few points
#      against the `ganzfeld sample` command itself.
#   4. Bad input in the page: a missing manifest and a roughness the tables lack: the page reports
#      the module's Error (naming the table set and what is allowed) and draws nothing.
# Usage: threejs_test.sh PATH/TO/ganzfeld PATH/TO/threejs_compare
set -u
G="$1"
COMPARE="$2"
. "$(dirname "$0")/harness.sh"
repository="$(cd "$(dirname "$0")/.." && pwd)"
package="$repository/js/ganzfeld-three"
BROWSER=$(chromium_binary)
[ -n "$BROWSER" ] && [ -x "$BROWSER" ] || { echo "FAIL: chromium-headless-shell is not installed (scripts/install-deps)"; exit 1; }
command -v node >/dev/null || { echo "FAIL: node is not installed (scripts/install-deps installs it)"; exit 1; }
[ -f "$package/node_modules/three/package.json" ] || { echo "FAIL: $package/node_modules/three is missing (scripts/install-deps runs npm ci)"; exit 1; }
SIZE=320x180      # the eight spheres cover ~9,000 pixels
MAX_ERROR=2e-2    # the example's tables (docs/three.md)

mkdir -p "$tmp/root"
ln -s "$repository/js" "$tmp/root/js"
ln -s "$repository/examples" "$tmp/root/examples"
for lights in extended all; do
  node "$package/bin/scene-file.js" "$repository/examples/three/scene.js" "$SIZE" "$lights" >"$tmp/$lights.json" \
    || { echo "FAIL: scene-file.js $lights"; exit 1; }
done
"$G" export-glsl --scene "$tmp/extended.json" --out "$tmp/root/t" --cache "$tmp/cache" --max-error "$MAX_ERROR" --quiet \
  || { echo "FAIL: export-glsl --scene"; exit 1; }
for lights in extended all; do
  "$G" render --scene "$tmp/$lights.json" --cache "$tmp/cache" --max-error "$MAX_ERROR" --quiet -o "$tmp/$lights.png" \
    || { echo "FAIL: render $lights"; exit 1; }
done

python3 -u -m http.server --bind 127.0.0.1 0 --directory "$tmp/root" >"$tmp/http.log" 2>&1 &
server=$!
trap 'kill -TERM $server 2>/dev/null; wait $server 2>/dev/null; rm -rf "$tmp"' EXIT
for _ in $(seq 100); do grep -qs "Serving HTTP" "$tmp/http.log" && break; sleep 0.1; done
port=$(sed -nE 's|^Serving HTTP on 127\.0\.0\.1 port ([0-9]+).*|\1|p' "$tmp/http.log")
[ -n "$port" ] || { echo "FAIL: no static server: $(cat "$tmp/http.log")"; exit 1; }

# load NAME PATH?QUERY: the DOM after the page's asynchronous work, in $tmp/NAME.html (the browser
# exits 0 even when the page failed: the page's own result is what is checked).
load() {
  "$BROWSER" "${CHROMIUM_FLAGS[@]}" --virtual-time-budget=120000 --user-data-dir="$tmp/profile" \
    --dump-dom "http://127.0.0.1:$port/$2" >"$tmp/$1.html" 2>"$tmp/$1.browser.log"
}
example() { load "$1" "examples/three/?test=1&size=$SIZE&tables=/t/manifest.json&$2"; }
result() { grep -o '<pre id="result"[^>]*>.\{0,400\}' "$tmp/$1.html"; }

# 2. Pixels.
example lambert "lights=extended&diffuse=lambert"
"$COMPARE" pixels "$tmp/extended.png" "$tmp/lambert.html" && ok || fail "lambert vs render: $(result lambert)"
example stock "lights=extended&diffuse=lambert&mode=stock"
"$COMPARE" pixels "$tmp/extended.png" "$tmp/stock.html" --expect-mismatch >"$tmp/stock.txt" && ok \
  || fail "stock three.js matched render: $(head -1 "$tmp/stock.txt")"
example sun "lights=all&diffuse=lambert"
"$COMPARE" pixels "$tmp/all.png" "$tmp/sun.html" --report >"$tmp/sun.txt" && ok || fail "with the sun: $(result sun)"
head -1 "$tmp/sun.txt"; grep '^json:' "$tmp/sun.txt"
example three "lights=extended"
"$COMPARE" pixels "$tmp/extended.png" "$tmp/three.html" --report >"$tmp/three.txt" && ok || fail "diffuse three: $(result three)"
head -1 "$tmp/three.txt"; grep '^json:' "$tmp/three.txt"

# 3. Lookups.
load lookup "js/ganzfeld-three/test/browser/lookup.html?tables=/t/manifest.json&points=1024&seed=1"
"$COMPARE" lookups "$tmp/cache" "$tmp/lookup.html" && ok || fail "lookups vs tables::sample: $(result lookup)"
python3 - "$tmp/lookup.html" "$tmp/cache" "$G" <<'PY' && ok || fail "lookups vs the ganzfeld sample command"
# The first point of every table through the command itself (it calls tables::sample, which the
# judge above uses at every point), within the judge's bound.
import glob, html, json, re, subprocess, sys
page = json.loads(html.unescape(re.search(r'<pre id="result">(.*?)</pre>', open(sys.argv[1]).read(), re.S).group(1)))
files = {}
for path in glob.glob(sys.argv[2] + '/*.exr'):
    info = json.loads(subprocess.run([sys.argv[3], 'info', path, '--json'], capture_output=True, text=True, check=True).stdout)
    files[(info['model'], info['law'])] = path
point = page['points'][0]
for s in page['sets']:
    for k, key in enumerate(['g0', 'g1', 'h0', 'h1']):
        law = 'g' if k < 2 else 'h'
        command = [sys.argv[3], 'sample', files[(s['models'][key], law)], '--json', '--j', '%.17g,%.17g,%.17g' % tuple(point[3:])]
        if law == 'g': command += ['--i', '%.17g,%.17g,%.17g' % tuple(point[:3])]
        cli = json.loads(subprocess.run(command, capture_output=True, text=True, check=True).stdout)['value']
        gpu = s['values'][k]
        assert abs(gpu - cli) <= 2e-5 + 1e-6, (s['models'][key], law, gpu, cli)  # the judge's bound for laws <= 1
PY

# 4. Bad input: an Error the page reports, no picture.
load missing "examples/three/?test=1&size=$SIZE&tables=/t/nosuch.json"
grep -q '"error":"ganzfeld-three: manifest .*/t/nosuch.json.: HTTP 404' "$tmp/missing.html" && ok || fail "missing manifest: $(result missing)"
python3 - "$tmp/root/t/manifest.json" "$tmp/root/t/partial.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
m['textures'] = [t for t in m['textures'] if 'alpha=0.16' not in t['model']]  # no tables of roughness 0.4
json.dump(m, open(sys.argv[2], 'w'))
PY
load partial "examples/three/?test=1&size=$SIZE&tables=/t/partial.json"
grep -q '"error":"ganzfeld-three: roughness 0.4 is outside the tables of manifest .*partial.json.; allowed: 0.5, 0.7, 0.9' \
  "$tmp/partial.html" && ok || fail "roughness outside the tables: $(result partial)"
! grep -q '"rgba"' "$tmp/partial.html" && ok || fail "the page drew a picture with a refused material"

[ -n "${KEEP:-}" ] && cp -r "$tmp" "$KEEP"
echo "threejs_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
