#!/usr/bin/env bash
# The load test of `ganzfeld serve` (bench/serve_load.cpp) in a short mode, for correctness only
# (timings are never asserted): 8 clients x 60 requests mixing /api/eval, cached and uncached
# /api/table get no error, and each uncached table is baked exactly once, by the answers, by the
# service's counter and by its access log. Then the bounded connections: with --max-connections
# open, one more gets 503 at once (the worker queue's bound: tests/worker_pool_test.cpp).
# Usage: serve_load_test.sh PATH/TO/ganzfeld PATH/TO/ganzfeld-load
set -u
G="$1"
LOAD="$2"
. "$(dirname "$0")/harness.sh"
pid=""
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null; rm -rf "$tmp"' EXIT

# --jobs 2 --queue 16: the 12 uncached tables always find a bake slot (bench/serve_load.cpp).
start_serve "$tmp/log" --cache "$tmp/cache" --jobs 2 --queue 16 && ok || { fail "serve did not start: $(cat "$tmp/log")"; exit 1; }
"$LOAD" --port "$port" --clients 8 --requests 60 --seed 7 >"$tmp/load.json" 2>"$tmp/load.err"
rc=$?
[ $rc -eq 0 ] && ok || fail "ganzfeld-load exit $rc: $(cat "$tmp/load.err") $(head -c 600 "$tmp/load.json")"
[ "$(json_field "$tmp/load.json" "(d['requests'], d['errors'], d['statuses'])")" = "(480, 0, {'200': 480})" ] \
  && ok || fail "load: $(json_field "$tmp/load.json" "(d['requests'], d['errors'], d['error_samples'])")"
[ "$(json_field "$tmp/load.json" "d['each_table_baked_once'] and d['tables_baked_by_server'] == d['uncached_tables_requested'] > 0")" = True ] \
  && ok || fail "baked once: $(json_field "$tmp/load.json" "(d['uncached_tables_requested'], d['tables_baked_by_server'])")"
# the access log: one "baked" line per uncached table, none for the cached set after its warm-up
n=$(json_field "$tmp/load.json" "d['uncached_tables_requested']")
[ "$(grep -E "GET /api/table\?model=specular:alpha=[0-9]+&law=g&res=16x16x8&tol=1e-6 200 .* baked " "$tmp/log" | sed -E 's/.*alpha=([0-9]+).*/\1/' | sort | uniq -c | awk '$1 == 1' | wc -l)" -eq "$n" ] \
  && ok || fail "access log: $(grep -c ' baked ' "$tmp/log") baked lines for $n tables"
[ "$(grep -E "minnaert.* baked " "$tmp/log" | wc -l)" -eq 8 ] && ok || fail "cached set baked other than once each"
# a second service on the same port is refused (httplib's default SO_REUSEPORT would let it share)
"$G" serve --cache "$tmp/cache2" --port "$port" 2>"$tmp/second.err" &
second=$!
for _ in $(seq 100); do kill -0 $second 2>/dev/null && ! grep -q "listening on" "$tmp/second.err" || break; sleep 0.1; done
if grep -q "listening on" "$tmp/second.err"; then kill -TERM $second; wait $second; fail "a second serve shares port $port"
else wait $second; rc=$?; [ $rc -eq 2 ] && grep -q "cannot listen on 127.0.0.1:$port" "$tmp/second.err" && ok || fail "second serve: exit $rc $(cat "$tmp/second.err")"; fi
kill -TERM $pid; wait $pid; pid=""

# --- bounded connections: --max-connections 4, held by idle connections (they send nothing; the
# connection loop holds them without a thread); the fifth gets 503 at once, not a place in an
# unbounded backlog, and once they close the service answers again.
start_serve "$tmp/log2" --cache "$tmp/cache" --max-connections 4 && ok || { fail "serve did not restart: $(cat "$tmp/log2")"; exit 1; }
held=()
for ((k = 0; k < 4; k++)); do exec {fd}<>"/dev/tcp/127.0.0.1/$port" && held+=("$fd"); done
sleep 0.3  # the loop accepts them
status=$(curl -s -m 3 -o "$tmp/body" -D "$tmp/headers" -w '%{http_code}' "http://127.0.0.1:$port/healthz")
[ "$status" = 503 ] && ok || fail "connection beyond --max-connections: status $status (want 503)"
json_field "$tmp/body" "d['error']" | grep -q "all 4 connections are open" && ok || fail "503 body: $(cat "$tmp/body")"
grep -qi '^Retry-After: [0-9]' "$tmp/headers" && grep -qi '^Connection: close' "$tmp/headers" && ok || fail "503 headers: $(cat "$tmp/headers")"
for fd in "${held[@]}"; do exec {fd}>&-; done
sleep 0.3
[ "$(curl -s -m 10 -o /dev/null -w '%{http_code}' "http://127.0.0.1:$port/healthz")" = 200 ] && ok || fail "no 200 after the held connections closed"
kill -TERM $pid; wait $pid; pid=""

echo "serve_load: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
