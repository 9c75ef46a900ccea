#!/usr/bin/env bash
# Installs what the libFuzzer harnesses (tests/fuzz) need on top of scripts/install-deps.sh: clang 14 and its
# runtime libraries (libFuzzer, sanitizers) from Debian 12 packages. Idempotent.
set -euo pipefail
pkgs=(clang-14 libclang-rt-14-dev)
missing=()
for p in "${pkgs[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if [ ${#missing[@]} -eq 0 ]; then echo "install-fuzz-deps: all packages present"; exit 0; fi
SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
echo "install-fuzz-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}" >/dev/null
