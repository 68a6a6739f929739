#!/bin/sh
# Rebuilds three.min.js: the classes of three.js the 3D page uses (entry.js), bundled and
# minified by esbuild into one script that defines the global THREE. Versions pinned in
# package.json / package-lock.json (from the npm registry). The page inlines the result, so
# it opens offline from disk; three.js's MIT licence is LICENSE here and in the page.
set -eu
cd "$(dirname "$0")"
npm ci --no-audit --no-fund
./node_modules/.bin/esbuild entry.js --bundle --minify --format=iife --global-name=THREE \
  --legal-comments=none --outfile=three.min.js
rm -rf node_modules
