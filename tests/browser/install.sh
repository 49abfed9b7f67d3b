#!/usr/bin/env bash
# Installs three.js (package.json, pinned by package-lock.json) into tests/browser/node_modules
# for the headless-browser test of the .glb output. Safe to run twice: npm ci runs only when
# the installed three is missing or not the locked version.
set -euo pipefail
cd "$(dirname "$0")"
want=$(sed -n 's/^ *"three": "\(.*\)"$/\1/p' package.json | head -1)
have=$(sed -n 's/^ *"version": "\(.*\)",$/\1/p' node_modules/three/package.json 2>/dev/null | head -1 || true)
if [ -n "$want" ] && [ "$want" = "$have" ]; then
  echo "tests/browser: three $have already installed"
  exit 0
fi
command -v npm >/dev/null 2>&1 || { echo "tests/browser: npm is missing (scripts/install-deps.sh installs it)" >&2; exit 1; }
npm ci --no-audit --no-fund
