#!/usr/bin/env bash
# `ganzfeld serve` over HTTP, as a browser or script sees it (docs/serve.md): endpoints and their
# JSON, ETag/304, refusals (400/413 + one-line JSON, the server lives on), no file outside the
# cache, single flight (8 identical requests -> one bake), 503 when the queue is full, SIGTERM.
# Hostile and careless clients: tests/serve_hostile_test.py.
# Usage: serve_test.sh PATH/TO/ganzfeld
set -u
G="$1"
. "$(dirname "$0")/harness.sh"
command -v curl >/dev/null || { echo "serve_test: curl is missing (scripts/install-deps installs it)"; exit 1; }

# A slow bake (a few seconds on 2 cores): long enough for concurrent requests to meet in flight.
SLOW="model=specular:alpha=8&law=g&res=40x40x20&tol=1e-10"
FAST="model=minnaert:xi=1&law=h&res=32"

# --jobs 1 --queue 0: one bake at a time, nothing waits, so a second distinct bake gets 503.
"$G" serve --cache "$tmp/cache" --port 0 --jobs 1 --queue 0 2>"$tmp/log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null; rm -rf "$tmp"' EXIT
for _ in $(seq 100); do grep -q "listening on" "$tmp/log" && break; sleep 0.1; done
port=$(sed -nE 's|.*listening on http://127\.0\.0\.1:([0-9]+)/.*|\1|p' "$tmp/log")
[ -n "$port" ] && ok || { fail "no listening line: $(cat "$tmp/log")"; exit 1; }
URL="http://127.0.0.1:$port"
# code PATH?QUERY [curl args]: the status; the body in $tmp/body, the headers in $tmp/headers
code() { local target="$1"; shift; rm -f "$tmp/body"; curl -s -o "$tmp/body" -D "$tmp/headers" -w '%{http_code}' "$@" "$URL$target"; }
header() { sed -nE "s/^$1: (.*)\r$/\1/Ip" "$tmp/headers"; }
alive() { kill -0 $pid 2>/dev/null; }

# --- health, the viewer's files (embedded; tests/viewer_test.sh runs them in a browser), the registry
[ "$(code /healthz)" = 200 ] && [ "$(json_field "$tmp/body" "d['status']")" = ok ] && ok || fail "/healthz"
[ "$(code /)" = 200 ] && grep -q '<script src="/viewer.js">' "$tmp/body" && header Content-Type | grep -q text/html && ok || fail "/ viewer page"
[ "$(code /viewer.js)" = 200 ] && grep -q "/api/table" "$tmp/body" && header Content-Type | grep -q text/javascript && ok || fail "/viewer.js"
[ "$(code "/?model=specular:alpha=8")" = 200 ] && ok || fail "/ with the viewer's own query"
# --- f's closed form as GLSL (the viewer's beam); a model without one is refused
[ "$(code "/api/glsl?model=0.5*minnaert:xi=1%2B0.5*specular:alpha=8&law=f")" = 200 ] \
  && grep -q "float gz_f_0_5_minnaert_xi_1_0_5_specular_alpha_8(vec3 i, vec3 j, vec3 n, vec3 t)" "$tmp/body" && [ -n "$(header ETag)" ] \
  && ok || fail "/api/glsl law=f: $(cat "$tmp/body")"
[ "$(code "/api/glsl?model=ggx:alpha=0.3&law=f")" = 200 ] && grep -q "float gz_f_ggx_alpha_0_3_[a-z0-9_]*(vec3 i, vec3 j, vec3 n, vec3 t)" "$tmp/body" \
  && ok || fail "/api/glsl law=f ggx: $(cat "$tmp/body")"
[ "$(code "/api/glsl?model=lambert&law=f&res=8")" = 400 ] && grep -q "unknown parameter 'res'" "$tmp/body" && ok || fail "/api/glsl law=f res"
"$G" models --json >"$tmp/models.json"
[ "$(code /api/models)" = 200 ] && \
  [ "$(python3 -c "import json; print(json.load(open('$tmp/body')) == json.load(open('$tmp/models.json')))")" = True ] \
  && ok || fail "/api/models differs from models --json"

# --- spec: the one parser's form and the canonical spec that eval --json names
[ "$(code "/api/spec?model=hvd-empirical:rsv=0.2,rsu=1,eta=1.5")" = 200 ] \
  && [ "$(json_field "$tmp/body" "d['canonical']")" = "$("$G" eval --model hvd-empirical:rsv=0.2,rsu=1,eta=1.5 --law f \
       --theta-i 0 --theta-j 0 --json | python3 -c "import json, sys; print(json.load(sys.stdin)['model'])")" ] \
  && [ "$(json_field "$tmp/body" "list(d['terms'][0]['parameters'])")" = "['eta', 'rsu', 'rsv']" ] \
  && ok || fail "/api/spec: $(cat "$tmp/body")"

# --- eval: the same value as the command line
"$G" eval --model specular:alpha=8 --law g --theta-i 60 --theta-j 30 --phi 180 --json >"$tmp/eval.json"
[ "$(code "/api/eval?model=specular:alpha=8&law=g&theta_i=60&theta_j=30&phi=180")" = 200 ] && ok || fail "/api/eval: $(cat "$tmp/body")"
[ "$(python3 -c "import json; a=json.load(open('$tmp/body')); b=json.load(open('$tmp/eval.json')); print(all(a[k]==b[k] for k in ('model','law','value','error','evaluations','converged','i','j')))")" = True ] \
  && ok || fail "/api/eval differs from eval --json: $(cat "$tmp/body")"
[ "$(code "/api/eval?model=0.5*lambert%2B0.5*minnaert:xi=1&law=h&theta_j=45")" = 200 ] && ok || fail "/api/eval of a mixture (%2B)"

# --- table: baked into the cache, ETag, 304, readable by `ganzfeld info`, the keys of `bake`
[ "$(code "/api/table?$FAST")" = 200 ] && [ "$(header X-Ganzfeld-Table)" = baked ] && ok || fail "/api/table: $(cat "$tmp/body")"
etag=$(header ETag)
[[ "$etag" =~ ^\"fnv1a64:[0-9a-f]{16}\"$ ]] && ok || fail "ETag '$etag'"
header Cache-Control | grep -q immutable && ok || fail "Cache-Control"
cp "$tmp/body" "$tmp/h.exr"
"$G" info "$tmp/h.exr" --json >"$tmp/info.json" && [ "$(json_field "$tmp/info.json" "(d['model'], d['law'], d['axes'][0]['count'])")" = "('minnaert:xi=1', 'h', 32)" ] \
  && ok || fail "the served table does not read with info"
cached=("$tmp"/cache/*.exr)
[ ${#cached[@]} -eq 1 ] && cmp -s "${cached[0]}" "$tmp/h.exr" && ok || fail "the cache holds ${#cached[@]} files / other bytes"
[ "$(json_field <("$G" bake --model minnaert:xi=1 --law h --res 32 --tol 1e-8 -o "${cached[0]}" --json) "d['tables'][0]['status']")" = reused ] \
  && ok || fail "bake does not reuse the service's cache entry (keys differ)"
[ "$(code "/api/table?$FAST" -H "If-None-Match: $etag")" = 304 ] && [ ! -s "$tmp/body" ] && ok || fail "If-None-Match -> 304"
[ "$(code "/api/table?$FAST" -H 'If-None-Match: "fnv1a64:0000000000000000"')" = 200 ] && ok || fail "other ETag -> 200"
[ "$(code "/api/table?$FAST&format=ktx2")" = 200 ] && [ "$(head -c 12 "$tmp/body" | od -An -c | tr -d ' \n')" = "253KTX20273\r\n032\n" ] \
  && ok || fail "format=ktx2"
[ "$(code "/api/table?$FAST&format=json")" = 200 ] && [ "$(json_field "$tmp/body" "(len(d['value']), d['law'])")" = "(32, 'h')" ] \
  && ok || fail "format=json"
# max_error: the table baked to a validated lookup error, as `bake --max-error` bakes it
[ "$(code "/api/table?model=specular:alpha=8&law=h&max_error=1e-5")" = 200 ] && ok || fail "max_error: $(cat "$tmp/body")"
"$G" info "$tmp/body" --json >"$tmp/maxerr.json" 2>&1 && ok || fail "the max_error table does not read"
[ "$(json_field "$tmp/maxerr.json" "d['target_error'] == 1e-5 and d['error'] <= 1e-5")" = "True" ] \
  && ok || fail "max_error table: $(cat "$tmp/maxerr.json")"
[ "$(code "/api/glsl?$FAST")" = 200 ] && grep -q "float gz_minnaert_xi_1_h(" "$tmp/body" && ok || fail "/api/glsl"

# --- bad requests: 400/413 with a one-line JSON error, and the server lives on
bad() {  # bad STATUS FRAGMENT TARGET
  local got; got=$(code "$3")
  if [ "$got" != "$1" ]; then fail "$3: status $got (want $1): $(cat "$tmp/body")"; return; fi
  if ! json_field "$tmp/body" "d['error']" | grep -qF -- "$2"; then fail "$3: error lacks '$2': $(cat "$tmp/body")"; return; fi
  [ "$(wc -l <"$tmp/body")" -eq 1 ] && ok || fail "$3: error is not one line"
}
bad 400 "names a data file" "/api/spec?model=merl:file=/etc/passwd"
bad 400 "unknown model 'nope'" "/api/eval?model=nope&law=h&theta_j=1"
bad 400 "alpha" "/api/eval?model=specular:alpha=-1&law=h&theta_j=1"
bad 400 "theta_j=91 is out of range" "/api/eval?model=lambert&law=h&theta_j=91"
bad 400 "unknown law 'q'" "/api/eval?model=lambert&law=q"
bad 400 "unknown parameter 'bogus'" "/api/eval?model=lambert&law=h&theta_j=1&bogus=2"
bad 400 "res='0x0' is not a resolution" "/api/table?model=lambert&law=h&res=0x0"
bad 400 "give res or max_error, not both" "/api/table?$FAST&max_error=1e-4"
bad 400 "max_error=0 is not allowed" "/api/table?model=lambert&law=h&max_error=0"
bad 413 "this service bakes at most" "/api/table?model=minnaert:xi=1&law=g&res=512"
alive && ok || fail "the server died on bad requests"

# --- nothing outside the cache can be read
bad 400 "unknown model '../../etc/passwd'" "/api/table?model=../../etc/passwd&law=h"
bad 400 "names a data file" "/api/table?model=merl:file=/etc/passwd&law=h"
bad 400 "names a data file" "/api/eval?model=tabulated:file=..%2F..%2Fetc%2Fpasswd&law=h&theta_j=1"
for target in "/..%2F..%2Fetc%2Fpasswd" "/api/table/..%2F..%2Fetc%2Fpasswd" "/../../etc/passwd" "/api/../../etc/passwd" "/etc/passwd"; do
  status=$(code "$target" --path-as-is)
  [[ "$status" =~ ^4 ]] && ! grep -q "root:" "$tmp/body" && ok || fail "$target: $status $(head -c 200 "$tmp/body")"
done

# --- single flight: 8 identical requests at once -> one bake, one file, one ETag
before=$(ls "$tmp"/cache/*.exr | wc -l)
for k in $(seq 8); do curl -s -o "$tmp/slow$k" -D "$tmp/slowh$k" -w '%{http_code}\n' "$URL/api/table?$SLOW" >"$tmp/slowcode$k" & done
sleep 0.5  # the bake runs: a distinct bake finds no free job and no queue slot
bad 503 "retry later" "/api/table?model=specular:alpha=9&law=g&res=40x40x20&tol=1e-10"
header Retry-After | grep -qE '^[0-9]+$' && ok || fail "503 without Retry-After"
wait $(jobs -p | grep -v "^$pid$") 2>/dev/null
[ "$(cat "$tmp"/slowcode* | sort -u)" = 200 ] && ok || fail "concurrent requests: $(cat "$tmp"/slowcode* | tr '\n' ' ')"
[ "$(cat "$tmp"/slowh* | grep -i '^etag' | sort -u | wc -l)" -eq 1 ] && ok || fail "concurrent requests got different ETags"
[ $(( $(ls "$tmp"/cache/*.exr | wc -l) - before )) -eq 1 ] && ok || fail "the cache gained other than one file"
[ "$(grep -F "GET /api/table?$SLOW 200" "$tmp/log" | grep -c ' baked ')" -eq 1 ] && ok || fail "log: not exactly one bake: $(grep -F "$SLOW" "$tmp/log")"
code /healthz >/dev/null
# three bakes so far: FAST, the max_error table and SLOW (once, however many asked)
[ "$(json_field "$tmp/body" "(d['tables_baked'], d['bakes_refused'] >= 1)")" = "(3, True)" ] && ok || fail "/healthz counters: $(cat "$tmp/body")"

# --- without --data: no files listed; f over a grid and the figure's sphere (serve/field.h)
[ "$(code /api/data)" = 200 ] && [ "$(json_field "$tmp/body" "(d['data'], d['files'])")" = "(False, [])" ] && ok \
  || fail "/api/data without --data: $(cat "$tmp/body")"
[ "$(code "/api/fgrid?model=lambert&theta=30&phi=0&res=4")" = 200 ] \
  && [ "$(json_field "$tmp/body" "(len(d['values']), round(min(d['values']) * 3.141592653589793, 9), round(max(d['values']) * 3.141592653589793, 9))")" = "(32, 1.0, 1.0)" ] \
  && ok || fail "/api/fgrid lambert: $(head -c 300 "$tmp/body")"
[ "$(code "/api/sphere?model=lambert&law=f&dir=0,0,1&size=8")" = 200 ] \
  && [ "$(json_field "$tmp/body" "(d['width'], len(d['value']), max(d['value']) > 0)")" = "(8, 64, True)" ] \
  && ok || fail "/api/sphere lambert: $(head -c 300 "$tmp/body")"
bad 400 "phi=400" "/api/fgrid?model=lambert&theta=30&phi=400&res=4"
bad 400 "names a data file" "/api/fgrid?model=merl:file=/etc/passwd&theta=30&phi=0&res=4"
bad 400 "law" "/api/sphere?model=lambert&law=a&dir=0,0,1&size=8"

# --- SIGTERM during a bake: its request is answered (200 if it ends within the drain, else 503:
# cancelled), no partial file, exit 0 (tests/serve_hostile_test.py: an endless bake)
curl -s -o "$tmp/last" -w '%{http_code}' "$URL/api/table?model=specular:alpha=7&law=g&res=40x40x20&tol=1e-10" >"$tmp/lastcode" &
curl_pid=$!
sleep 0.5
kill -TERM $pid
wait $pid; status=$?
wait $curl_pid
[ $status -eq 0 ] && ok || fail "exit $status after SIGTERM"
grep -q "shutting down on SIGTERM" "$tmp/log" && ok || fail "no shutdown line"
[[ "$(cat "$tmp/lastcode")" =~ ^(200|503)$ ]] && ok || fail "the in-flight bake was not answered: $(cat "$tmp/lastcode")"
ls "$tmp/cache" | grep -q tmp && fail "partial files in the cache: $(ls "$tmp/cache")" || ok
for f in "$tmp"/cache/*; do "$G" info "$f" >/dev/null || fail "unreadable cache file $f"; done
curl -s -m 2 "$URL/healthz" >/dev/null && fail "still answering after SIGTERM" || ok

# --- --data DIR: files by name, never a path; a missing directory is one line and exit 2
expect_bad "is not a directory" serve --cache "$tmp/cache2" --data "$tmp/no-such-dir" --port 0
mkdir -p "$tmp/data"
"$G" export-brdf --model lambert --format tabulated --res 3x3x3 -o "$tmp/data/flat.tab" >/dev/null || fail "export-brdf"
echo "not a BRDF" >"$tmp/data/notes.txt"
start_serve "$tmp/data_log" --cache "$tmp/cache2" --data "$tmp/data" || fail "serve --data did not start: $(cat "$tmp/data_log")"
[ "$(code /api/data)" = 200 ] \
  && [ "$(json_field "$tmp/body" "([f['name'] for f in d['files']], [f['spec'] for f in d['files']], len(d['skipped']))")" \
       = "(['flat.tab'], ['tabulated:file=flat.tab'], 1)" ] && ok || fail "/api/data: $(cat "$tmp/body")"
[ "$(code "/api/eval?model=tabulated:file=flat.tab&law=f&theta_i=30&theta_j=40&phi=10")" = 200 ] \
  && json_field "$tmp/body" "d['model']" | grep -q "file=flat.tab" && ! grep -qF "$tmp/data" "$tmp/body" && ok \
  || fail "a listed file by name: $(cat "$tmp/body")"
bad 404 "no data file 'x.tab'" "/api/eval?model=tabulated:file=x.tab&law=h&theta_j=1"
bad 404 "no data file '../data/flat.tab'" "/api/eval?model=tabulated:file=../data/flat.tab&law=h&theta_j=1"
bad 404 "no data file '$tmp/data/flat.tab'" "/api/eval?model=tabulated:file=$tmp/data/flat.tab&law=h&theta_j=1"
bad 400 "no GLSL form of f" "/api/glsl?model=tabulated:file=flat.tab&law=f"
kill -TERM $pid; wait $pid

echo "serve: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
