#!/usr/bin/env bash
# The benchmarks build and run in CI in their short mode; this checks the JSON shapes they
# print (never timings: those are reported, not asserted).
set -eu
G="$1"; tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$G" bench cubature --quick --json >"$tmp/c.json"
python3 - "$tmp/c.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
need = {"oracle", "hcubature_lune", "hcubature_naive", "pcubature_lune", "boost_gauss_kronrod", "boost_tanh_sinh"}
assert len(d["families"]) >= 6, d["families"]
for f in d["families"]:
    assert f["cases"] > 0, f["name"]
    assert need <= set(f["evals_ratio"]), (f["name"], f["evals_ratio"].keys())
    assert all(r > 0 for r in f["evals_ratio"].values()), f["name"]
    assert 0 <= f["missed_rate"] <= 1 and f["mc_error_ratio_equal_time"] > 0
PY
"$G" bench bake --quick --json >"$tmp/b.json"
python3 -c "import json,sys; d=json.load(open('$tmp/b.json')); assert len(d['tables'])==2 and all(t['speedup_2_threads']>0 for t in d['tables'])"
"$G" bench render --quick --json >"$tmp/r.json"
python3 -c "import json; d=json.load(open('$tmp/r.json')); r=d['ratios']; assert r['tables_vs_lambert']>0 and r['direct_vs_tables']>0"
# The real-time tables' report: every section and a verdict on each target.
"$G" bench realtime --quick --markdown "$tmp/realtime.md"
for section in "Per-texel error bound" "Bake time" "White furnace" "independent estimator"; do grep -q "$section" "$tmp/realtime.md"; done
[ "$(grep -cE '\*\*(met|missed)\*\*' "$tmp/realtime.md")" -ge 14 ]
# Genz's families (bench/genz_bench.h): docs/reliability-genz.md with a verdict per target.
"$G" bench genz --quick --markdown - >"$tmp/genz.md"
grep -q "Dishonest runs" "$tmp/genz.md"
[ "$(grep -cE '\*\*(met|missed)\*\*' "$tmp/genz.md")" -ge 4 ]
# Bad input: one line, exit code 2 (a tolerance <= 0, NaN or below what doubles resolve; a budget
# below one panel; an unknown benchmark).
for bad in "genz --tolerances 0" "genz --tolerances -1e-6" "genz --tolerances nan" "genz --tolerances 1e-17" \
           "genz --budget 100" "nonsense"; do
  set +e; "$G" bench $bad 2>"$tmp/err" >/dev/null; code=$?; set -e
  [ "$code" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] || { echo "bench $bad: exit $code: $(cat "$tmp/err")"; exit 1; }
done
echo "bench smoke: 1 passed, 0 failed"
