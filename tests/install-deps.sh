#!/usr/bin/env bash
# Installs the Debian 12 packages nightcap builds, runs and tests with, when any is missing.
# Run as root (or through sudo). Does nothing when everything is present.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers
  glslang-tools glslang-dev
  libopenimageio-dev openimageio-tools libopenexr-dev
  libglm-dev libtinygltf-dev nlohmann-json3-dev libcli11-dev
  libzstd-dev libxxhash-dev zlib1g-dev libdeflate-dev libgtest-dev renderdoccmd python3-renderdoc
  graphviz chromium spirv-tools libedit-dev
  clang-14 libfuzzer-14-dev libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
