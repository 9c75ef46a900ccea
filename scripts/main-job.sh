#!/usr/bin/env bash
# Installs the dependencies, builds jetshell (Release, -march=native) and runs the headline job: the slit
# annular ring validation (the page's 325-vertex example and Sze et al.'s plate), printing where the tables,
# frames and pictures are. Usage: bash scripts/main-job.sh [out-dir]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out}"
bash scripts/install-deps.sh
cmake -S . -B build-native -DCMAKE_BUILD_TYPE=Release -DJETSHELL_NATIVE=ON -DJETSHELL_BUILD_TESTS=OFF
cmake --build build-native -j"$(nproc)" --target jetshell
js=build-native/jetshell
mkdir -p "$out"
echo "== Slit annular ring (the page's example, 325 vertices, dynamic relaxation) =="
$js run examples/slit_annular_ring.json --out "$out/slit_annular_ring"
echo
echo "== Validation against Sze et al. (2004) =="
$js validate --all --json "$out/validation.json" --plots "$out/validation" || true
echo
echo "Outputs:"
echo "  $out/slit_annular_ring/   frames (.vtu + .pvd for ParaView), probes.csv, summary.json, final.png"
echo "  $out/validation.json      validation tables; plots in $out/validation/"
