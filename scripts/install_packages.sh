#!/usr/bin/env bash
# Installs the Debian packages named on the command line that are missing (as root, or
# through sudo; non-interactive). Shared by setup.sh and sanitize.sh.
# Usage: bash scripts/install_packages.sh TAG PACKAGE...   (TAG prefixes the message)
set -euo pipefail
tag=$1
shift
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "$tag: installing ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
