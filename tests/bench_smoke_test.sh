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
set +e; "$G" bench nonsense 2>"$tmp/err"; code=$?; set -e
[ "$code" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ]
echo "bench smoke: 1 passed, 0 failed"
