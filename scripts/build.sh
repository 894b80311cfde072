#!/usr/bin/env bash
# Configures and builds SuperLoc in ./build (Release). Extra args go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
WERROR=OFF
if [ "${CI:-}" = "true" ]; then WERROR=ON; fi
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSUPERLOC_WERROR=$WERROR "$@"
cmake --build build -j "$(nproc)"
