#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and builds tests/consumer against it with
# find_package(ganzfeld), then runs the consumer; with PYTHON, imports the installed Python package
# from PYTHON_DIR under the prefix and evaluates a law with it.
# Usage: install_consumer_test.sh BUILD_DIR CONSUMER_DIR [PYTHON PYTHON_DIR]
set -euo pipefail
build=$1 consumer=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
cmake -S "$consumer" -B "$tmp/build" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/build" >/dev/null
"$tmp/build/consumer"
python=${3:-} python_dir=${4:-}
if [ -n "$python" ]; then
  case $python_dir in /*) ;; *) python_dir=$tmp/prefix/$python_dir ;; esac
  PYTHONPATH=$python_dir "$python" -c 'import ganzfeld, sys
assert ganzfeld.__file__.startswith(sys.argv[1]), ganzfeld.__file__
print("python:", ganzfeld.Model("lambert").h(theta_j=30).value)' "$python_dir"
fi
