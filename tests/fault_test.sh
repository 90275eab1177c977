#!/usr/bin/env bash
# Faults on every file ganzfeld writes: after a kill -9 at a random moment,
# a file-size limit, a full disk, a read-only or impossible output, and eight processes sharing
# one cache, every target path holds nothing or a complete valid file, the cache holds only
# valid entries, and refusals are one line with exit 2.
# Usage: fault_test.sh [--markdown] PATH/TO/ganzfeld [TRIALS] [SEED]
#   --markdown  print the "faults" section of docs/reliability.md on stdout (the trials per command
#               and their outcomes, each refusal and concurrency check); the log goes to stderr
#               (scripts/docs --reliability pipes it into scripts/doc-section)
set -u
markdown=0
[ "${1:-}" = "--markdown" ] && { markdown=1; shift; exec 3>&1 1>&2; }
G="$1"
TRIALS="${2:-200}"
SEED="${3:-20261125}"
RANDOM=$SEED  # seeds bash's generator: the trial sequence is reproducible
. "$(dirname "$0")/harness.sh"
scene="$(dirname "$0")/../examples/default.json"
small=(--res-g 9x9x5 --res-h 17 --tol 1e-6)

# --- the summary's rows: note LABEL closes a check (passed when no fail since the previous note)
checks=() noted_failed=0
note() {
  checks+=("| $1 | $([ "$failed" -eq "$noted_failed" ] && echo passed || echo "**failed** ($((failed - noted_failed)))") |")
  noted_failed=$failed
}
skip() { checks+=("| $1 | skipped: $2 |"); echo "SKIP: $1: $2"; }

# --- validators: a complete file of each kind, read back the way a user would
valid_table() { "$G" info "$1" >/dev/null 2>&1; }
valid_png() {
  python3 - "$1" <<'EOF'
import struct, sys, zlib
data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n'
pos, chunks = 8, []
while pos < len(data):
    n, = struct.unpack('>I', data[pos:pos + 4]); kind = data[pos + 4:pos + 8]
    body = data[pos + 8:pos + 8 + n]; crc, = struct.unpack('>I', data[pos + 8 + n:pos + 12 + n])
    assert len(body) == n and zlib.crc32(kind + body) == crc
    chunks.append(kind); pos += 12 + n
assert chunks[0] == b'IHDR' and chunks[-1] == b'IEND'
EOF
}
valid_glsl_dir() {  # export-glsl --scene: the shader and manifest are complete, every listed texture exists
  python3 - "$1" <<'EOF' 2>/dev/null
import json, os, sys
d = sys.argv[1]
if not os.path.exists(os.path.join(d, 'manifest.json')):   # manifest written last: nothing promised yet
    sys.exit(0)
m = json.load(open(os.path.join(d, 'manifest.json')))
for t in m['textures']:
    assert os.path.getsize(os.path.join(d, t['file'])) > 0
EOF
  [ ! -e "$1/ganzfeld_scene.glsl" ] || tail -c 200 "$1/ganzfeld_scene.glsl" | grep -q "return vec3(0.0);"
}
valid_brdf() { "$G" eval --model "merl:file=$1" --law f --theta-i 10 --theta-j 20 >/dev/null 2>&1; }
valid_cache() {  # every entry the cache would serve reads cleanly
  local f
  for f in "$1"/*.exr; do [ -e "$f" ] || continue; valid_table "$f" || return 1; done
}

# --- kill -9 at a random moment (seeded), TRIALS times over five writers
cache="$tmp/kill_cache"
writers=("bake" "bake --scene (cache)" "export-glsl --scene" "export-brdf" "render")
declare -a runs killed nothing complete invalid
for k in 0 1 2 3 4; do runs[k]=0 killed[k]=0 nothing[k]=0 complete[k]=0 invalid[k]=0; done
# outcome KIND: what the killed writer left, one of nothing / complete (read back whole) / invalid
outcome() {
  case $1 in
    0) [ ! -e "$target" ] && echo nothing && return; valid_table "$target" ;;
    1) [ -z "$(ls "$cache"/*.exr 2>/dev/null)" ] && echo nothing && return; valid_cache "$cache" ;;
    2) valid_glsl_dir "$target" || { echo invalid; return; }; [ -e "$target/manifest.json" ] || { echo nothing; return; } ;;
    3) [ ! -e "$target" ] && echo nothing && return; valid_brdf "$target" ;;
    4) [ ! -e "$target" ] && echo nothing && return; valid_png "$target" ;;
  esac && echo complete || echo invalid
}
for ((trial = 0; trial < TRIALS; trial++)); do
  kind=$((trial % 5))
  case $kind in
    0) target="$tmp/kill_g.exr"; cmd=(bake --model specular:alpha=8 --law g --res 33x33x17 --tol 1e-6 -o "$target" --force --quiet); max_ms=800 ;;
    1) target="$cache"; cmd=(bake --scene "$scene" --out "$cache" --res-g 17x17x9 --res-h 33 --tol 1e-6 --force --quiet); max_ms=600 ;;
    2) target="$tmp/kill_glsl"; rm -rf "$target"; cmd=(export-glsl --scene "$scene" --out "$target" "${small[@]}" --texture header --quiet); max_ms=300 ;;
    3) target="$tmp/kill.binary"; cmd=(export-brdf --model minnaert:xi=0.5 --format merl -o "$target"); max_ms=250 ;;
    4) target="$tmp/kill.png"; cmd=(render --scene "$scene" "${small[@]}" -o "$target" --quiet); max_ms=350 ;;
  esac
  [ "$kind" -ne 1 ] && [ "$kind" -ne 2 ] && rm -f "$target"
  delay_ms=$((RANDOM % max_ms))
  "$G" "${cmd[@]}" >/dev/null 2>&1 &
  pid=$!
  sleep "$(printf '0.%03d' "$delay_ms")"
  kill -9 "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  [ $? -eq 137 ] && killed[kind]=$((killed[kind] + 1))  # 128 + SIGKILL: it was still running
  runs[kind]=$((runs[kind] + 1))
  left=$(outcome "$kind")
  case $left in
    nothing) nothing[kind]=$((nothing[kind] + 1)) ;;
    complete) complete[kind]=$((complete[kind] + 1)) ;;
    *) invalid[kind]=$((invalid[kind] + 1)); fail "trial $trial (${writers[kind]}, killed after ${delay_ms} ms): invalid $target" ;;
  esac
done
note "kill -9: every target holds nothing or a complete valid file"
# The next run over a killed cache reads or re-bakes every entry and leaves it valid.
"$G" bake --scene "$scene" --out "$cache" --res-g 17x17x9 --res-h 33 --tol 1e-6 --quiet >/dev/null && valid_cache "$cache" \
  && ok || fail "a killed cache is not usable by the next bake"
note "kill -9: the next \`bake --scene\` over the killed cache leaves every entry valid"
leftovers=$(find "$tmp" -name '.*.tmp-*' | wc -l)
for k in 0 1 2 3 4; do
  echo "kill -9, ${writers[k]}: ${runs[k]} trials, ${killed[k]} killed while running; nothing ${nothing[k]}," \
       "complete ${complete[k]}, invalid ${invalid[k]}"
done
echo "kill -9: $TRIALS trials (seed $SEED); temporary files left by killed processes: $leftovers"

# --- file-size limit (ulimit -f): one line, exit 2, no target and no temporary file
limited() { (ulimit -f 8; "$G" "$@"); }  # 8 KiB
for writer in table render brdf glsl; do
  rm -rf "$tmp/lim"; mkdir "$tmp/lim"
  case $writer in
    table) limited bake --model specular:alpha=8 --law g --res 33x33x17 --tol 1e-4 -o "$tmp/lim/g.exr" --quiet ;;
    render) limited render --scene "$scene" "${small[@]}" -o "$tmp/lim/r.png" --quiet ;;
    brdf) limited export-brdf --model minnaert:xi=0.5 --format merl -o "$tmp/lim/m.binary" ;;
    glsl) limited export-glsl --scene "$scene" --out "$tmp/lim/out" "${small[@]}" --texture header --quiet ;;
  esac >/dev/null 2>"$tmp/lim.err"
  rc=$?
  [ "$rc" -eq 2 ] && [ "$(wc -l <"$tmp/lim.err")" -eq 1 ] && ok || fail "ulimit -f, $writer: exit $rc, stderr: $(cat "$tmp/lim.err")"
  [ -z "$(find "$tmp/lim" -name '.*.tmp-*')" ] && [ ! -e "$tmp/lim/g.exr" ] && [ ! -e "$tmp/lim/r.png" ] &&
    [ ! -e "$tmp/lim/m.binary" ] && [ ! -e "$tmp/lim/out/ganzfeld_scene.glsl" ] \
    && ok || fail "ulimit -f, $writer left: $(find "$tmp/lim" -type f)"
  note "file-size limit (\`ulimit -f 8\`), $writer: one line, exit 2, no target or temporary file"
done

# --- a full disk: a 64 KiB tmpfs where mounting is permitted (root in a container, not always in CI)
full="$tmp/full"; mkdir -p "$full"
if mount -t tmpfs -o size=64k tmpfs "$full" 2>/dev/null; then
  "$G" bake --model specular:alpha=8 --law g --res 33x33x17 --tol 1e-4 -o "$full/g.exr" --quiet >/dev/null 2>"$tmp/full.err"
  [ $? -eq 2 ] && [ "$(wc -l <"$tmp/full.err")" -eq 1 ] && ok || fail "disk full: $(cat "$tmp/full.err")"
  [ -z "$(ls -A "$full")" ] && ok || fail "disk full left: $(ls -A "$full")"
  "$G" render --scene "$scene" "${small[@]}" -o "$full/r.png" --quiet 2>"$tmp/full.err"
  # a 512x512 PNG may fit in 64 KiB: either written whole or refused in one line with nothing left
  { [ -e "$full/r.png" ] && valid_png "$full/r.png"; } || { [ -z "$(ls -A "$full")" ] && [ "$(wc -l <"$tmp/full.err")" -eq 1 ]; } \
    && ok || fail "disk full, render: $(ls -A "$full") $(cat "$tmp/full.err")"
  umount "$full"
  note "disk full (a 64 KiB tmpfs), bake and render: one line, exit 2, nothing left (or a whole PNG)"
else
  skip "disk full (a 64 KiB tmpfs)" "mounting a tmpfs is not permitted here; the file-size limit covers the writers"
fi

# --- read-only output and cache directories (as an unprivileged user: root may write anywhere)
ro="$tmp/ro"; mkdir -p "$ro"; chmod 555 "$ro"; chmod 755 "$tmp"
as_nobody() { setpriv --reuid=65534 --regid=65534 --clear-groups "$G" "$@"; }
if command -v setpriv >/dev/null && [ "$(id -u)" -eq 0 ]; then
  chmod o+rx "$tmp" "$(dirname "$tmp")" 2>/dev/null
  as_nobody bake --model specular:alpha=8 --law h --res 9 -o "$ro/h.exr" >/dev/null 2>"$tmp/ro.err"
  [ $? -eq 2 ] && grep -q "not writable" "$tmp/ro.err" && ok || fail "read-only output: $(cat "$tmp/ro.err")"
  as_nobody bake --scene "$scene" --out "$ro" "${small[@]}" >/dev/null 2>"$tmp/ro.err"
  [ $? -eq 2 ] && grep -q "not a writable directory" "$tmp/ro.err" && ok || fail "read-only cache: $(cat "$tmp/ro.err")"
  [ -z "$(ls -A "$ro")" ] && ok || fail "read-only directory gained: $(ls -A "$ro")"
  note "read-only output and cache directories: one line, exit 2, the directory unchanged"
else
  skip "read-only output and cache directories" "needs root to drop to an unprivileged user"
fi

# --- an output path that is a directory
mkdir -p "$tmp/adir.exr"
expect_bad "is a directory" bake --model specular:alpha=8 --law h --res 9 -o "$tmp/adir.exr"
expect_bad "is a directory" render --scene "$scene" "${small[@]}" -o "$tmp/adir.exr"
note "output path that is a directory, bake and render: one line, exit 2"

# --- eight processes, one cache: the same and different tables at once
shared="$tmp/shared"; mkdir -p "$shared"
for p in 1 2 3 4 5 6 7 8; do
  res=$((p % 2 ? 17 : 33))  # two different table sets, four processes each
  "$G" bake --scene "$scene" --out "$shared" --res-g 9x9x5 --res-h "$res" --tol 1e-6 --json --quiet >"$tmp/shared$p.json" 2>&1 &
done
wait
valid_cache "$shared" && ok || fail "a concurrently baked cache entry is invalid"
[ "$(ls "$shared"/*.exr | wc -l)" -eq 9 ] && ok || fail "expected 9 tables (3 g shared + 2 x 3 h), found: $(ls "$shared")"
for p in 1 2 3 4 5 6 7 8; do
  [ "$(json_field "$tmp/shared$p.json" "len(d['tables'])==6 and all(t['status'] in ('baked','reused') for t in d['tables'])")" = "True" ] \
    && ok || fail "process $p: $(cat "$tmp/shared$p.json")"
done
[ -z "$(find "$shared" -name '.*.tmp-*')" ] && ok || fail "temporary files left in the shared cache"
statuses=$(cat "$tmp"/shared?.json | python3 -c "import json, sys
d = json.JSONDecoder(); s = sys.stdin.read().strip(); n = {}
while s:
    doc, end = d.raw_decode(s); s = s[end:].strip()
    for t in doc['tables']: n[t['status']] = n.get(t['status'], 0) + 1
print(', '.join(f'{v} {k}' for k, v in sorted(n.items())))" 2>/dev/null)
note "8 processes, one cache (4 x 2 table sets): 9 valid tables, every process's 6 tables baked or reused ($statuses)"

if [ "$markdown" -eq 1 ]; then
  {
    echo "## Fault trials: every file ganzfeld writes"
    echo
    echo "Generated by \`tests/fault_test.sh --markdown build/ganzfeld $TRIALS $SEED\` (do not edit by hand; ctest runs"
    echo "the same trials as \`fault_test\`) on $(date -u +%Y-%m-%d), commit $(git -C "$(dirname "$0")" rev-parse --short HEAD 2>/dev/null || echo unknown)."
    echo
    echo "kill -9 at a random moment (bash's RANDOM seeded with $SEED): $TRIALS trials, the five writers in turn, each"
    echo "killed after a random delay below its typical run time. *Killed while running* counts the trials whose"
    echo "process died of the signal (the others had finished); the split between *nothing* and *complete* depends"
    echo "on the machine's speed, *invalid* (a partial or unreadable file, or an invalid cache entry) must be 0."
    echo "For \`bake --scene\` the target is the cache directory (complete: every entry reads back); for"
    echo "\`export-glsl --scene\` it is the output directory (complete: manifest, shader and every listed texture)."
    echo
    echo "| command | trials | killed while running | nothing | complete and valid | invalid |"
    echo "|---|---|---|---|---|---|"
    for k in 0 1 2 3 4; do
      echo "| \`${writers[k]}\` | ${runs[k]} | ${killed[k]} | ${nothing[k]} | ${complete[k]} | ${invalid[k]} |"
    done
    echo
    echo "Temporary files left behind by killed processes: $leftovers (a later write of the same target replaces"
    echo "them; readers never open them)."
    echo
    echo "| check | outcome |"
    echo "|---|---|"
    printf '%s\n' "${checks[@]}"
    echo
    echo "- 0 invalid files after $TRIALS kill -9 trials: **$([ "$(( ${invalid[0]} + ${invalid[1]} + ${invalid[2]} + ${invalid[3]} + ${invalid[4]} ))" -eq 0 ] && echo met || echo missed)**."
    echo "- every refusal and the concurrency check passed: **$([ "$failed" -eq 0 ] && echo met || echo missed)** ($passed checks passed, $failed failed)."
  } >&3
fi

echo "fault: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
