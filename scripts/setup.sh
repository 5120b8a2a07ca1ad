#!/usr/bin/env bash
# Installs the Debian packages the project needs (only those missing), then configures and builds
# the project in Release into build/. Used by `make train` and `make test`.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make libtorch-dev libbullet-dev libeigen3-dev libyaml-cpp-dev libgloo-dev
          libopenblas0-pthread libgtest-dev python3-torch
          gnuplot-nox zlib1g-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# the replay viewer: npm installs three.js at build time, and its test drives Debian's Chromium
# (a Node.js from elsewhere that brings its own npm is kept)
command -v npm > /dev/null || missing+=(nodejs npm)
[ -x /usr/bin/chromium ] || missing+=(chromium)
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing missing packages: ${missing[*]}"
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs"
