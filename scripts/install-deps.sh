#!/usr/bin/env bash
# Installs jetshell's build and run dependencies from Debian 12 packages. Idempotent.
set -euo pipefail
pkgs=(build-essential cmake libeigen3-dev libceres-dev libsuitesparse-dev libnlopt-dev libnlopt-cxx-dev
      catch2 nlohmann-json3-dev libcli11-dev gnuplot-nox libpng-dev)
missing=()
for p in "${pkgs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -eq 0 ]; then echo "install-deps: all packages present"; exit 0; fi
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
