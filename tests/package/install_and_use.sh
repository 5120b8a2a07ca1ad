#!/usr/bin/env bash
# Installs the toolkit from BUILD_DIR into a temporary prefix, then configures, builds and runs
# tests/package/external_project against the installed package alone (ctest: package_test).
set -euo pipefail
build_dir=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
test -f "$work/prefix/lib/cmake/rlt/rltConfig.cmake"
test -f "$work/prefix/include/rlt/rl/trainer/training_run.h"
test -x "$work/prefix/bin/rlt"
# the installed rlt finds the installed replay viewer (when the build made one: npm was there)
if [ -f "$build_dir/viewer/site/index.html" ]; then
  test -f "$work/prefix/share/rlt/viewer/vendor/three/three.module.js"
  printf '{"format":"rlt-recording","version":2,"episodes":[]}' > "$work/empty.json"
  served=$(timeout 3 "$work/prefix/bin/rlt" replay "$work/empty.json" --port 0 || true)
  echo "$served" | grep -q "http://127.0.0.1:" || { echo "installed rlt replay: $served"; exit 1; }
fi
cmake -S "$here/external_project" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
cmake --build "$work/build" -j"$(nproc)" > "$work/build.log" || { cat "$work/build.log"; exit 1; }
"$work/build/train_sign_game"
