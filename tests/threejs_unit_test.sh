#!/usr/bin/env bash
# js/ganzfeld-three under Node's test runner (its test/*.test.js): the KTX2 reader, the table checks
# and their errors, the table sets by roughness, the material checks and the three.js scene file.
# Usage: threejs_unit_test.sh PATH/TO/ganzfeld
set -u
package="$(cd "$(dirname "$0")/../js/ganzfeld-three" && pwd)"
command -v node >/dev/null || { echo "FAIL: node is not installed (scripts/install-deps installs it)"; exit 1; }
[ -f "$package/node_modules/three/package.json" ] || { echo "FAIL: $package/node_modules/three is missing (scripts/install-deps runs npm ci)"; exit 1; }
G=$(realpath "$1")
cd "$package" && GANZFELD="$G" exec node --test test/*.test.js
