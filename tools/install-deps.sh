#!/usr/bin/env bash
# Installs the Debian packages nfrc needs; a no-op (under a second) when all are present.
set -euo pipefail
packages=(build-essential cmake libeigen3-dev libsuitesparse-dev libsundials-dev
          nlohmann-json3-dev doctest-dev python3 python3-matplotlib
          python3-dev python3-pybind11 python3-pytest python3-numpy
          clang libfuzzer-14-dev libclang-rt-14-dev libspectra-dev libfftw3-dev
          libsiconos-numerics-dev libopenblas-dev liblapacke-dev libopenmpi-dev openmpi-bin)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
