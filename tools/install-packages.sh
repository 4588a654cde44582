#!/usr/bin/env bash
# Installs those of the named Debian packages that are missing (as root, or
# through sudo), so that the scripts beside it run on a fresh machine.
#
#   tools/install-packages.sh PACKAGE...
set -euo pipefail

sudo=""
[ "$(id -u)" -eq 0 ] || sudo=sudo
missing=()
# Installed means "install ok installed": a package removed but not purged keeps
# its configuration files, and dpkg -s still describes it.
for p in "$@"; do
  [ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null)" = "install ok installed" ] || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "== installing ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
