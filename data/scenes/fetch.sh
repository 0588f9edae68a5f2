#!/usr/bin/env bash
# Fetches the third-party models data/scenes/*.json render into data/scenes/models/ and checks every
# file against data/scenes/SHA256SUMS; `data/scenes/fetch.sh --help` says how. The work is in
# fetch.py (Python 3 standard library only), which can convert the armadillo's PLY and hash files
# portably where a shell cannot.
set -euo pipefail
if ! command -v python3 >/dev/null; then
  echo "fetch.sh: error: python3 is needed (Debian: apt-get install python3)" >&2
  exit 1
fi
exec python3 "$(dirname "$0")/fetch.py" "$@"
