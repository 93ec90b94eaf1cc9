#!/usr/bin/env bash
# Installs the Debian packages the project needs, only those missing.
# Needs root (or sudo) when something is missing; does nothing otherwise.
set -euo pipefail

packages=(
  build-essential cmake
  libceres-dev libeigen3-dev libsuitesparse-dev
  libspectra-dev  # Sparse eigenvalues (pose-graph certificate).
  # The BLAS under CHOLMOD's supernodal factorizations (3D pose graphs, the
  # certificate); single-threaded, so results do not depend on the cores.
  libopenblas0-serial
  libopencv-dev libgflags-dev libgoogle-glog-dev libyaml-cpp-dev
  libgtest-dev libgmock-dev
  python3 python3-yaml python3-numpy python3-opencv zlib1g-dev libbz2-dev
  clang libclang-rt-14-dev bzip2  # Fuzzing (scripts/fuzz.sh).
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all packages present"
  exit 0
fi

echo "install_deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
