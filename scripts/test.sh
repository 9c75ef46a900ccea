#!/usr/bin/env bash
# Installs the dependencies, builds jetshell (portable Release) and runs the whole test
# suite with CTest. Usage: bash scripts/test.sh [build-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-test}"
bash scripts/install-deps.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DJETSHELL_NATIVE=OFF
cmake --build "$build" -j"$(nproc)"
cd "$build"
ctest --output-on-failure -j"$(nproc)" --timeout 900
