#!/usr/bin/env bash
# ganzfeld fit as a user runs it: bad input (one line, exit 2), JSON, a fit that does not converge
# (exit 0, converged false), Ctrl-C (the best fit so far, exit 0), the report's quick mode, the disk
# view and export-brdf --noise.
set -u
G="$1"
source "$(dirname "$0")/harness.sh"

"$G" export-brdf --model ward:rho_d=0.4,rho_s=0.2,alpha=0.15 -o "$tmp/ward.binary" >/dev/null || fail "export-brdf"
printf 'not a MERL file' >"$tmp/bad.binary"

# Bad input.
expect_bad "cannot read MERL file" fit --data merl:file="$tmp/missing.binary" --model ward
expect_bad "allowed: 90x90x180" fit --data merl:file="$tmp/bad.binary" --model ward
expect_bad "no free parameter" fit --data merl:file="$tmp/ward.binary" --model lambert
expect_bad "no free parameter" fit --data merl:file="$tmp/ward.binary" --model perfect-backscatter
expect_bad "unknown parameter 'beta'" fit --data merl:file="$tmp/ward.binary" --model ward --fixed beta=1
expect_bad "out of range" fit --data merl:file="$tmp/ward.binary" --model ward --fixed alpha=3
expect_bad "unknown --metric 'l2'" fit --data merl:file="$tmp/ward.binary" --model ward --metric l2
expect_bad "unknown --local" fit --data merl:file="$tmp/ward.binary" --model ward --local newton
expect_bad "does not divide" fit --data merl:file="$tmp/ward.binary" --model ward --grid 90x40x30
expect_bad "is not the model" fit --data merl:file="$tmp/ward.binary" --model ward --start ggx
expect_bad "unknown model" fit --data merl:file="$tmp/ward.binary" --model wardd
expect_bad "--starts" fit --data merl:file="$tmp/ward.binary" --model ward --starts 0
expect_bad "needs --data" fit --model ward
expect_bad "--report needs --markdown" fit --report
expect_bad "--noise" export-brdf --model ward --noise -0.1 -o "$tmp/x.binary"
expect_bad "must end in .png" figure --disk --model ward -o "$tmp/disk.exr"
expect_bad "--theta-o 95" figure --disk --model ward --theta-o 0,95 -o "$tmp/disk.png"
[ ! -e "$tmp/x.binary" ] && [ ! -e "$tmp/disk.png" ] && ok || fail "a refused command left a file"

# A fit to its own model's file: converged, the parameters back, the laws of both.
if "$G" fit --data merl:file="$tmp/ward.binary" --model ward --grid 45x15x15 --json >"$tmp/fit.json"; then
  python3 - "$tmp/fit.json" <<'PY' && ok || fail "fit JSON: $(head -c 600 "$tmp/fit.json")"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] is True and d["interrupted"] is False, d
p = d["parameters"]
assert abs(p["alpha"] - 0.15) < 1e-5 and abs(p["rho_d"] - 0.4) < 1e-5 and abs(p["rho_s"] - 0.2) < 1e-5, p
assert d["spec"].startswith("ward:") and d["metrics"]["ngan_relative"] < 1e-6 and d["samples"] > 1000
laws = d["laws"]
assert len(laws["points"]) == 12 and laws["max_difference"]["h"] < 1e-3, laws["max_difference"]
PY
else fail "fit ward exit $?"; fi

# Not converged: the best point, said so, exit 0.
if "$G" fit --data merl:file="$tmp/ward.binary" --model ward --max-evals 5 --starts 1 --no-laws --json >"$tmp/nc.json"; then
  json_field "$tmp/nc.json" "d['converged'] is False and d['stop_reason'] == 'evaluation budget reached' and d['spec'] != ''" |
    grep -q True && ok || fail "not converged JSON: $(cat "$tmp/nc.json")"
else fail "a fit that does not converge must exit 0"; fi
"$G" fit --data merl:file="$tmp/ward.binary" --model ward --max-evals 5 --starts 1 --no-laws >"$tmp/nc.txt" &&
  grep -q "NOT converged" "$tmp/nc.txt" && ok || fail "the text output must say NOT converged"

# Ctrl-C: the search stops and prints the best fit so far.
"$G" fit --data cook-torrance --model hvd-fit --starts 1000 --max-evals 1000000 --no-laws --json >"$tmp/int.json" 2>"$tmp/int.err" &
pid=$!
sleep 3
kill -INT "$pid"
wait "$pid"; code=$?
if [ "$code" -eq 0 ]; then
  json_field "$tmp/int.json" "d['interrupted'] is True and d['converged'] is False and d['spec'].startswith('hvd-fit:')" |
    grep -q True && ok || fail "Ctrl-C JSON: $(cat "$tmp/int.json")"
else fail "Ctrl-C: exit $code (want 0 with the best fit so far) $(cat "$tmp/int.err")"; fi

# The report's quick mode: every part, a verdict per target, the disk figure.
if "$G" fit --report --quick --quiet --markdown "$tmp/fitting.md" >/dev/null; then
  for section in "## Targets" "## 1. Synthetic recovery" "## 2. Two lumps" "## 3. Cross-model table" "## 4. The halfway-vector disk view"; do
    grep -qF "$section" "$tmp/fitting.md" && ok || fail "report lacks $section"
  done
  [ "$(grep -cE '\| \*\*(met|missed)\*\* \|' "$tmp/fitting.md")" -eq 5 ] && ok || fail "report: not 5 verdicts"
  [ -s "$tmp/figures/fit-disk-plastic.png" ] && ok || fail "report: no disk figure"
else fail "fit --report --quick"; fi

# The disk view on its own.
"$G" figure --disk --model merl:file="$tmp/ward.binary" --compare ward:alpha=0.3 --theta-o 0,60 -o "$tmp/d.png" >/dev/null &&
  [ -s "$tmp/d.png" ] && ok || fail "figure --disk"

echo "fit cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
