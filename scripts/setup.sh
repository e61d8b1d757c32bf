#!/usr/bin/env bash
# Installs the Debian packages sinkwatch builds and tests with, when they are
# missing. Idempotent: a machine that has them all does nothing and needs no
# network. Never downloads anything but Debian packages.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  clang clang-tidy cppcheck libclang-rt-14-dev llvm
  googletest libgtest-dev libgmock-dev librapidcheck-dev libbenchmark-dev
  libeigen3-dev libceres-dev libcli11-dev libboost-dev
  gcc-arm-none-eabi libstdc++-arm-none-eabi-newlib binutils-arm-none-eabi
  g++-arm-linux-gnueabihf qemu-user
  gnuplot-nox gcovr valgrind
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ "${#missing[@]}" -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${#missing[@]} missing packages: ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
