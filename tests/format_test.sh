#!/usr/bin/env bash
# Every tracked C++ source follows .clang-format (scripts/format --check): one layout, checked, so
# a change's diff holds its change and nothing else.
# Usage: format_test.sh SOURCE_DIR
set -eu
exec "$1/scripts/format" --check
