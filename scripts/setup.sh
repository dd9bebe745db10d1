#!/usr/bin/env bash
# One idempotent set-up step: install every Debian package the suite needs (listed in
# scripts/debian-packages.txt), then build the workspace in Release with -j2.
#   scripts/setup.sh            install what is missing, then build
#   scripts/setup.sh --no-build install only
# Uses sudo only when not root; runs `apt-get update` at most once; installs nothing when all
# packages are present.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# shellcheck source=env.sh
source "$root/scripts/env.sh"

build=1
[ "${1:-}" = "--no-build" ] && build=0

mapfile -t wanted < <(grep -vE '^\s*(#|$)' "$root/scripts/debian-packages.txt" | awk '{print $1}')
missing=()
for p in "${wanted[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${#missing[@]} missing Debian package(s): ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "setup: not root and no sudo: install as root: ${missing[*]}" >&2; exit 1; }
    SUDO="sudo"
  fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#wanted[@]} Debian packages present"
fi

if [ $build -eq 1 ]; then
  cd "$root"
  echo "setup: building (Release, -j2)"
  catkin_make --source . -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
    -DCATKIN_ENABLE_TESTING=ON -DCATKIN_WHITELIST_PACKAGES="" -j2
fi
