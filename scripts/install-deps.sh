#!/usr/bin/env bash
# Installs jetshell's build and run dependencies from Debian 12 packages, and selects OpenBLAS (OpenMP build) as
# the system BLAS/LAPACK that CHOLMOD and jetshell's supernodal factorization use (libblas-dev and liblapack-dev
# give the linker libblas.so and liblapack.so). Idempotent. Usage: bash scripts/install-deps.sh [--tests]
# OpenBLAS's OpenMP build shares libgomp's thread pool with jetshell's element loops, so the two never run more
# threads than OMP_NUM_THREADS between them (the pthread build would keep a second pool). jetshell works with any
# BLAS: this only makes the factorizations faster (about 2× against Debian's default reference/ATLAS BLAS).
set -euo pipefail
pkgs=(build-essential cmake ninja-build libeigen3-dev libceres-dev libsuitesparse-dev libnlopt-dev libnlopt-cxx-dev
      catch2 nlohmann-json3-dev libcli11-dev libcairo2-dev fonts-dejavu-core libpng-dev libblas-dev liblapack-dev
      libopenblas0-openmp)
# --tests: also what the test command needs beyond the build (scripts/test.sh): valgrind for the memcheck test.
[ "${1:-}" = "--tests" ] && pkgs+=(valgrind)
missing=()
for p in "${pkgs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
else
  echo "install-deps: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
fi
# Select OpenBLAS-OpenMP for libblas.so.3 and liblapack.so.3 (another provider may have been chosen by hand).
arch="$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)"
for lib in libblas.so.3 liblapack.so.3; do
  target="/usr/lib/$arch/openblas-openmp/$lib"
  if [ -e "$target" ]; then
    current="$(readlink -f "/usr/lib/$arch/$lib" || true)"
    if [ "$current" != "$(readlink -f "$target")" ]; then
      $SUDO update-alternatives --set "$lib-$arch" "$target"
    fi
  fi
done
