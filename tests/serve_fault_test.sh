#!/usr/bin/env bash
# kill -9 of `ganzfeld serve` in the middle of a bake: the
# cache it leaves holds no partial file, the next `serve` answers from it (reusing what was
# finished, baking what was lost) and `bake` reads every entry without error. Also: a temporary
# file left by a writer killed mid-rename and a truncated entry are ignored / re-baked, never served.
# Usage: serve_fault_test.sh PATH/TO/ganzfeld
set -u
G="$1"
. "$(dirname "$0")/harness.sh"
command -v curl >/dev/null || { echo "serve_fault_test: curl is missing (scripts/install-deps installs it)"; exit 1; }

# A bake of about 5 s on 2 cores, so the kill lands while it runs even when the rest of the suite
# loads the machine, and a quick one.
SLOW="model=specular:alpha=8&law=g&res=64x64x32&tol=1e-10"
SLOW_BAKE=(--model specular:alpha=8 --law g --res 64x64x32 --tol 1e-10)
FAST="model=minnaert:xi=1&law=h&res=32"
FAST_BAKE=(--model minnaert:xi=1 --law h --res 32 --tol 1e-8)  # serve's default tol: scene::TableOptions
cache="$tmp/cache"
pid=""
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null; rm -rf "$tmp"' EXIT

get() { curl -s -o "$tmp/body" -D "$tmp/headers" -w '%{http_code}' "$URL$1"; }  # status; body, headers
table_status() { sed -nE 's/^X-Ganzfeld-Table: (.*)\r$/\1/Ip' "$tmp/headers"; }
# bakes_running from /healthz without starting an interpreter per poll (the poll must be quick).
running() { curl -s "$URL/healthz" | sed -nE 's/.*"bakes_running": *([0-9]+).*/\1/p'; }
entries() { ls -A "$cache"; }

start_serve "$tmp/log1" --cache "$cache" && ok || { fail "serve did not start: $(cat "$tmp/log1")"; exit 1; }
[ "$(get "/api/table?$FAST")" = 200 ] && [ "$(table_status)" = baked ] && ok || fail "fast table: $(cat "$tmp/body")"
fast_file=$(entries)
curl -s -o /dev/null "$URL/api/table?$SLOW" &
client=$!
for _ in $(seq 200); do [ "$(running)" = 1 ] && break; sleep 0.05; done
[ "$(running)" = 1 ] && ok || fail "the slow bake never ran"
kill -9 $pid
wait $pid 2>/dev/null; status=$?
wait $client 2>/dev/null
[ $status -eq 137 ] && ok || fail "serve exit $status after kill -9 (want 137: killed)"
pid=""
[ "$(entries)" = "$fast_file" ] && ok || fail "after kill -9 the cache holds: $(entries | tr '\n' ' ') (want only $fast_file)"

# What a writer killed between writing and renaming leaves (util/atomic_file.h names it
# .NAME.tmp-PID-N), and an entry cut short: neither may be served.
head -c 1000 "$cache/$fast_file" >"$cache/.$fast_file.tmp-999999-0"
cp "$cache/$fast_file" "$tmp/fast.exr"
head -c 1000 "$tmp/fast.exr" >"$cache/$fast_file"

# --- the next serve over the same cache
start_serve "$tmp/log2" --cache "$cache" && ok || { fail "serve did not restart: $(cat "$tmp/log2")"; exit 1; }
[ "$(get "/api/table?$FAST")" = 200 ] && [ "$(table_status)" = baked ] && ok || fail "truncated table not re-baked: $(table_status)"
cmp -s "$tmp/body" "$tmp/fast.exr" && cmp -s "$cache/$fast_file" "$tmp/fast.exr" && ok || fail "the re-baked table differs from the first bake"
[ "$(get "/api/table?$FAST")" = 200 ] && [ "$(table_status)" = reused ] && ok || fail "fast table not reused: $(table_status)"
[ "$(get "/api/table?$SLOW")" = 200 ] && [ "$(table_status)" = baked ] && ok || fail "slow table after restart: $(table_status) $(head -c 200 "$tmp/body")"
"$G" info "$tmp/body" >/dev/null && ok || fail "the re-baked slow table does not read"
kill -TERM $pid; wait $pid; pid=""

# --- bake reads every entry the service left: reused, not re-baked, no error
slow_file=$(ls "$cache" | grep -v "^$fast_file$")
[ "$(echo "$slow_file" | wc -w)" -eq 1 ] && ok || fail "the cache holds: $(entries | tr '\n' ' ')"
for f in "$fast_file" "$slow_file"; do "$G" info "$cache/$f" >/dev/null || fail "unreadable cache entry $f"; done
reused() { "$G" bake "$@" --json | python3 -c "import json,sys; print(json.load(sys.stdin)['tables'][0]['status'])"; }
[ "$(reused "${FAST_BAKE[@]}" -o "$cache/$fast_file")" = reused ] && ok || fail "bake does not reuse $fast_file"
[ "$(reused "${SLOW_BAKE[@]}" -o "$cache/$slow_file")" = reused ] && ok || fail "bake does not reuse $slow_file"
"$G" bake --scene "$(dirname "$0")/../examples/default.json" --out "$cache" --res-g 9x9x5 --res-h 17 --tol 1e-6 --quiet \
  >/dev/null && ok || fail "bake --scene over the killed cache failed"

echo "serve_fault: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
