#!/bin/sh
# Refresh the vendored JavaScript of `cosim app` from npm (not run by any build): ml-matrix's
# UMD bundle and its license. Usage: cosim/app/static/vendor/update.sh [VERSION]; then update
# the version and the SHA-256 sums in README.md (printed at the end) and run tests/test_app.py.
set -eu
version="${1:-6.15.1}"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack --silent "ml-matrix@$version" >/dev/null && tar xzf "ml-matrix-$version.tgz")
cp "$work/package/matrix.umd.js" "$here/ml-matrix.umd.js"
cp "$work/package/LICENSE" "$here/LICENSE-ml-matrix"
sha256sum "$work/ml-matrix-$version.tgz" "$here/ml-matrix.umd.js"
