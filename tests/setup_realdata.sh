#!/bin/sh
# Fixture for the realdata tests: make sure Debian's mricron-data is there.
f=/usr/share/mricron/templates/aal.nii.gz
[ -f "$f" ] && exit 0
if [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mricron-data >/dev/null 2>&1 ||
        { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq mricron-data >/dev/null; }
fi
[ -f "$f" ] || { echo "missing $f: install Debian's mricron-data (scripts/install-deps.sh)" >&2; exit 1; }
