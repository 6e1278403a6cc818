#!/usr/bin/env bash
# Sets up a Debian 12 machine for luxloc and builds it (Release) into ./build.
# Idempotent and non-interactive: installs only the Debian packages that are missing
# (as root, or through sudo), then configures and builds. Usage: bash scripts/setup.sh
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(build-essential cmake ninja-build pkg-config git
          libeigen3-dev libopencv-dev libv4l-dev libtbb-dev libcli11-dev catch2 libbenchmark-dev zlib1g-dev
          socat opencv-doc
          libmosquitto-dev mosquitto mosquitto-clients libcpp-httplib-dev chromium)

bash scripts/install_packages.sh setup "${PACKAGES[@]}"

BUILD_DIR=${LUXLOC_BUILD_DIR:-build}
JOBS=${LUXLOC_JOBS:-$(nproc)}
# ccache, when the machine has it, makes rebuilds of other checkouts (worktrees) cheap.
LAUNCHER=()
if command -v ccache >/dev/null 2>&1; then LAUNCHER=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache); fi
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "${LAUNCHER[@]}" >/dev/null
cmake --build "$BUILD_DIR" -j "$JOBS"
echo "setup: built $BUILD_DIR/luxloc"
