#!/bin/sh
# Refresh the vendored JavaScript of `cosim app` from npm (not run by any build): ml-matrix's
# UMD bundle and three.js (an IIFE defining the global THREE, derived from three's ESM build by
# esbuild, since three >= 0.160 ships no classic-script build), each with its license.
# Usage: cosim/app/static/vendor/update.sh [ML_MATRIX_VERSION [THREE_VERSION [ESBUILD_VERSION]]];
# then update the versions and the SHA-256 sums in README.md (printed at the end) and run
# tests/test_app.py and tests/test_animate.py.
set -eu
version="${1:-6.15.1}"
three="${2:-0.187.0}"
esbuild="${3:-0.28.2}"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack --silent "ml-matrix@$version" >/dev/null && tar xzf "ml-matrix-$version.tgz")
cp "$work/package/matrix.umd.js" "$here/ml-matrix.umd.js"
cp "$work/package/LICENSE" "$here/LICENSE-ml-matrix"
mkdir "$work/three"
(cd "$work/three" && npm pack --silent "three@$three" >/dev/null && tar xzf "three-$three.tgz")
# three.module.js imports three.core.js; bundle both into one minified classic script whose
# top-level `var THREE` is window.THREE (no import, no require: inlined into file:// pages).
(cd "$work/three" && npx --yes "esbuild@$esbuild" package/build/three.module.js --bundle --format=iife \
  --global-name=THREE --minify --legal-comments=inline --log-level=warning \
  "--banner:js=/* three.js $three (MIT, see LICENSE-three): package/build/three.module.js bundled by esbuild $esbuild --bundle --format=iife --global-name=THREE --minify */" \
  --outfile="$here/three.min.js")
cp "$work/three/package/LICENSE" "$here/LICENSE-three"
sha256sum "$work/ml-matrix-$version.tgz" "$here/ml-matrix.umd.js" "$work/three/three-$three.tgz" "$here/three.min.js"
