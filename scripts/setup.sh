#!/usr/bin/env bash
# Installs Penumbra's build dependencies from Debian 12 packages.
# Idempotent: when everything is present it only checks (about a second).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libembree-dev libtbb-dev libopenimageio-dev openimageio-tools libtinyobjloader-dev libassimp-dev libtinygltf-dev
  libpugixml-dev libdeflate-dev            # libdeflate: PNG output without OpenImageIO
  libgtest-dev libcli11-dev nlohmann-json3-dev
  python3-dev pybind11-dev python3-numpy python3-pytest python3-openimageio
  python3-venv python3-pip python3-setuptools python3-wheel python3-nbconvert python3-ipykernel
  gnuplot-nox
  clang libclang-rt-14-dev
  libopenmpi-dev openmpi-bin
  libcivetweb-dev                           # the web server of penumbra --preview
  chromium chromium-driver python3-selenium # the preview's test in a real browser
)

missing=()
for p in "${packages[@]}"; do
  # dpkg-query reports "install ok installed" only for fully installed packages.
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "setup: missing packages: ${missing[*]}" >&2
if [[ $(id -u) -ne 0 ]]; then
  echo "setup: error: installing packages needs root; run as root or: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
apt-get update -q
apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "setup: installed ${missing[*]}" >&2
