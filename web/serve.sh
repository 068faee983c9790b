#!/usr/bin/env bash
# Serves the repository root (index.html) on http://127.0.0.1:${PORT:-8000}/.
set -euo pipefail
cd "$(dirname "$0")/.."
[ -f web/pkg/relief.js ] || { echo "web/pkg is missing: run bash web/build.sh first" >&2; exit 1; }
echo "relief: http://127.0.0.1:${PORT:-8000}/"
exec python3 -m http.server "${PORT:-8000}" --bind 127.0.0.1
