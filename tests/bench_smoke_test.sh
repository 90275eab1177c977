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
python3 -c "import json; d=json.load(open('$tmp/r.json')); r=d['ratios']; assert r['tables_vs_lambert']['median']>0 and r['direct_vs_tables']['median']>0 and len(r['tables_vs_lambert']['runs'])==d['repeats']"
"$G" bench render --quick --markdown >"$tmp/render.md"
grep -q "scripts/doc-section docs/realtime.md render" "$tmp/render.md"
[ "$(grep -cE '\*\*(met|missed)\*\*' "$tmp/render.md")" -eq 1 ]
# The real-time tables' report: every section and a verdict on each target.
"$G" bench realtime --quick --markdown >"$tmp/realtime.md"
for section in "Per-texel error bound" "Bake time" "White furnace" "independent estimator"; do grep -q "$section" "$tmp/realtime.md"; done
[ "$(grep -cE '\*\*(met|missed)\*\*' "$tmp/realtime.md")" -ge 14 ]
# The shaders benchmark on Mesa llvmpipe (small tables, a 128² pass): every pass timed and counted,
# every table's exported lookup against tables::sample, a verdict on each GPU-cost target.
"$G" bench shaders --quick --platform surfaceless --json >"$tmp/s.json"
python3 - "$tmp/s.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["gl_renderer"] and d["software"] and d["timer"].startswith("wall")
names = [p["name"] for p in d["passes"]]
assert names[:2] == ["A", "S"] and len(names) >= 4, names
assert any(p["define"] == "GANZFELD_HARDWARE_FILTER" for p in d["passes"])
for p in d["passes"]:
    assert p["milliseconds"]["median"] > 0 and p["fetches_per_pixel"] >= 0, p["name"]
    for law in p["laws"]:
        assert law["points"] >= 1000 and law["fetches"] >= 1, (p["name"], law)
        # llvmpipe: the same numbers in float (texelFetch, and its full-precision linear filter)
        assert law["max_difference"] <= 1e-4 * max(1.0, law["lookup_error"]), (p["name"], law)
assert d["passes"][0]["fetches_per_pixel"] == 0 and d["passes"][1]["fetches_per_pixel"] == 2
PY
"$G" bench shaders --quick --platform surfaceless --frames 3 --markdown >"$tmp/shaders.md"
grep -q "scripts/doc-section docs/realtime.md shaders-software" "$tmp/shaders.md"
[ "$(grep -cE '\*\*(met|missed)\*\*' "$tmp/shaders.md")" -ge 3 ]
set +e; "$G" bench shaders --quick --platform moon 2>"$tmp/err"; code=$?; set -e
[ "$code" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ]
set +e; "$G" bench render --markdown docs/x.md 2>"$tmp/err"; code=$?; set -e
[ "$code" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ]
# Genz's families (bench/genz_bench.h): docs/reliability-genz.md with a verdict per target.
"$G" bench genz --quick --markdown - >"$tmp/genz.md"
grep -q "Dishonest runs" "$tmp/genz.md"
[ "$(grep -oE '\*\*(met|missed)\*\*' "$tmp/genz.md" | wc -l)" -ge 4 ]  # two verdicts a line
grep -q "≥ 500 instances per family and dimension, each at every relative tolerance 1e-3, 1e-4, …, 1e-12: \*\*missed\*\* (3 instances; 2 of the 10 tolerances" "$tmp/genz.md"  # --quick: a smaller sample says so
# Bad input: one line, exit code 2 (a tolerance <= 0, NaN or below what doubles resolve; a budget
# below one panel; an unknown benchmark).
for bad in "genz --tolerances 0" "genz --tolerances -1e-6" "genz --tolerances nan" "genz --tolerances 1e-17" \
           "genz --budget 100" "genz --markdown" "genz --markdown x.md" "nonsense"; do
  set +e; "$G" bench $bad 2>"$tmp/err" >/dev/null; code=$?; set -e
  [ "$code" -eq 2 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] || { echo "bench $bad: exit $code: $(cat "$tmp/err")"; exit 1; }
done
echo "bench smoke: 1 passed, 0 failed"
