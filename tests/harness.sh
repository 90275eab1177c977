# Shared by the shell tests (source it after setting G, the ganzfeld executable): a temporary
# directory $tmp removed at exit, pass/fail counters and the refusal check (one line, exit code 2).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
passed=0 failed=0
ok()   { passed=$((passed + 1)); }
fail() { failed=$((failed + 1)); echo "FAIL: $*"; }

# expect_bad "fragment of the message" args...: exit 2, exactly one stderr line containing the fragment
expect_bad() {
  local fragment="$1"; shift
  "$G" "$@" >"$tmp/out" 2>"$tmp/err"; local code=$?
  local lines; lines=$(wc -l <"$tmp/err")
  if [ "$code" -ne 2 ]; then fail "exit $code (want 2): $*"; return; fi
  if [ "$lines" -ne 1 ]; then fail "$lines stderr lines (want 1): $*"; return; fi
  if ! grep -qF -- "$fragment" "$tmp/err"; then fail "stderr lacks '$fragment': $* -> $(cat "$tmp/err")"; return; fi
  ok
}
json_field() { python3 -c "import json,sys; d=json.load(open('$1')); print($2)"; }
# start_serve LOG [serve args]: `$G serve --port 0 ARGS` in the background, stderr to LOG; waits for
# its listening line and sets pid, port and URL; fails (status 1) if it never listens.
start_serve() {
  local log="$1"; shift
  "$G" serve --port 0 "$@" 2>"$log" &
  pid=$!
  for _ in $(seq 100); do grep -q "listening on" "$log" && break; sleep 0.1; done
  port=$(sed -nE 's|.*listening on http://127\.0\.0\.1:([0-9]+)/.*|\1|p' "$log")
  URL="http://127.0.0.1:$port"
  [ -n "$port" ]
}
# Debian's chromium-headless-shell: the real binary in the package's lib directory (the wrapper on
# PATH misparses the flags), and the flags every headless run here needs: WebGL2 through
# SwiftShader, and no background connections (the test machines reach no network: Chromium's own
# update, sync and QUIC attempts would be refused, many at a time).
chromium_binary() { dpkg -L chromium-headless-shell 2>/dev/null | grep -m1 '^/usr/lib/.*/chromium-headless-shell$'; }
CHROMIUM_FLAGS=(--no-sandbox --headless --use-angle=swiftshader --enable-unsafe-swiftshader --disable-background-networking
                --disable-component-update --disable-sync --no-first-run --disable-quic)
