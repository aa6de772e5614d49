#!/bin/sh
# Builds and runs the tests of fmi2_runtime.c.  Exit code non-zero on any failure.
#
#   1. the harness, with -Wall -Wextra -Wpedantic -Werror (-O2, then -O0 with ASan/UBSan), with
#      three other FMUs (the runtime with other models) as shared libraries for the FMU-state tests
#   2. the runtime as a shared library exactly as `cosim build` compiles it; checks the exports
#   3. if cmake is available: fmpy's CMake project (plain cc, all warnings, no -lm)
set -eu

here=$(cd "$(dirname "$0")" && pwd)
runtime=$(dirname "$here")
fmi=${FMI2_HEADERS:-$(python3 -c "import fmpy, os; print(os.path.join(os.path.dirname(fmpy.__file__), 'c-code'))")}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
CC=${CC:-gcc}
warn="-std=c99 -Wall -Wextra -Wpedantic -Werror"

# The other FMUs of the FMU-state tests (see harness.c): the runtime with another model, built
# like an FMU binary.  $1: extra compiler flags, $2: file name suffix.
others() {
    $CC $warn $1 -fPIC -shared -fvisibility=hidden -I"$fmi" -I"$runtime" "$runtime/fmi2_runtime.c" \
        "$here/test_model_small.c" -o "$out/small$2.so" -lm
    $CC $warn $1 -fPIC -shared -fvisibility=hidden -I"$fmi" -I"$runtime" "$runtime/fmi2_runtime.c" \
        "$here/test_model_small.c" "-DTEST_MODEL_GUID=\"$guid\"" -o "$out/small_same_guid$2.so" -lm
    $CC $warn $1 -fPIC -shared -fvisibility=hidden -I"$fmi" -I"$runtime" "$runtime/fmi2_runtime.c" \
        "$here/test_model.c" "-DTEST_MODEL_GUID=\"$twin_guid\"" -o "$out/twin$2.so" -lm
    $CC $warn $1 -fPIC -shared -fvisibility=hidden -I"$fmi" -I"$runtime" "$runtime/fmi2_runtime.c" \
        "$here/test_model_init.c" -o "$out/init$2.so" -lm
}
guid='{8c4e810f-3df3-4a00-8276-176fa3c9f000}'      # test_model.c (GUID in harness.c)
twin_guid='{8c4e810f-3df3-4a00-8276-176fa3c9f001}' # TWIN_GUID in harness.c
san="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"

echo "== harness (-O2)"
others "-O2" ""
$CC $warn -O2 -I"$fmi" -I"$runtime" "$here/harness.c" "$here/test_model.c" "$runtime/fmi2_runtime.c" \
    -o "$out/harness" -lm -ldl
"$out/harness" "$out/small.so" "$out/small_same_guid.so" "$out/twin.so" "$out/init.so"

echo "== harness (-O0, address and undefined behaviour sanitizers)"
others "-O0 -g $san" "_san"
$CC $warn -O0 -g $san -I"$fmi" -I"$runtime" "$here/harness.c" "$here/test_model.c" "$runtime/fmi2_runtime.c" \
    -o "$out/harness_san" -lm -ldl
"$out/harness_san" "$out/small_san.so" "$out/small_same_guid_san.so" "$out/twin_san.so" "$out/init_san.so" > "$out/san.log" 2>&1 ||
    { cat "$out/san.log"; exit 1; }
tail -n 1 "$out/san.log"

echo "== shared library as built by cosim build"
$CC -std=c99 -O2 -fPIC -shared -fvisibility=hidden -Wall -Wextra -Werror -I"$fmi" -I"$runtime" \
    "$runtime/fmi2_runtime.c" "$here/test_model.c" -o "$out/model.so" -lm
exports=$(nm -D --defined-only "$out/model.so" | awk '$2 == "T" { print $3 }' | sort)
expected=$(grep -o 'FMI2_Export fmi2[A-Za-z]*TYPE *fmi2[A-Za-z]*' "$fmi/fmi2Functions.h" | awk '{ print $3 }' | sort)
if [ "$exports" != "$expected" ]; then
    echo "exported symbols differ from the FMI 2.0 API:"
    echo "$exports" > "$out/a"; echo "$expected" > "$out/b"; diff "$out/a" "$out/b" || true
    exit 1
fi
echo "exports: $(echo "$exports" | wc -l) fmi2 functions, nothing else"
if command -v cmake > /dev/null 2>&1; then
    echo "== fmpy CMake project (cc, FMI_ALL_WARNINGS, no -lm)"
    mkdir -p "$out/cmake" "$out/target"
    cmake -S "$fmi" -B "$out/cmake" -DFMI_MODEL_IDENTIFIER=model -DFMI_ALL_WARNINGS=ON \
        "-DFMI_INCLUDE_DIRS=$runtime" "-DFMI_SOURCES=$runtime/fmi2_runtime.c" \
        "-DFMI_TARGET_DIR=$out/target" > "$out/cmake.log" 2>&1 || { cat "$out/cmake.log"; exit 1; }
    # the runtime alone: its own warnings, and no undefined symbols beyond libc and COSIM_MODEL
    cmake --build "$out/cmake" > "$out/build.log" 2>&1 || { cat "$out/build.log"; exit 1; }
    if grep -i "warning" "$out/build.log"; then echo "warnings in the CMake build"; exit 1; fi
    undefined=$(nm -u "$out/cmake/model.so" | awk '{ print $2 }' | grep -v -e '^COSIM_MODEL$' \
        -e '^__' -e '^_ITM' -e '^memcpy' -e '^memset' -e '^memcmp' -e '^strcmp' -e '^strlen' -e '^vsnprintf' || true)
    if [ -n "$undefined" ]; then echo "unexpected undefined symbols: $undefined"; exit 1; fi
    echo "builds warning-free; needs only libc (memcpy, memset, memcmp, strcmp, strlen, vsnprintf)"
fi
echo "== all runtime tests passed"
