#!/bin/sh
# Builds and runs the tests of the runtime: the core cosim_runtime.c with the FMI 2.0 API fmi2_api.c
# and with the FMI 3.0 API fmi3_api.c.  Exit code non-zero on any failure.
#
#   1. the FMI 2 harness (harness.c), with -Wall -Wextra -Wpedantic -Werror (-O2, then -O0 with
#      ASan/UBSan), with four other FMUs (the runtime with other models) as shared libraries for the
#      FMU-state and initial-equation tests
#   2. the FMI 3 harness (harness3.c, both APIs linked, to compare FMI 3 with FMI 2), the same way,
#      with two other FMI 3 FMUs
#   3. step_factor.c: the integrator's step size factor against its full formula, bit for bit;
#      tape_harness.c: the tape interpreter cosim_tape.c (-O2, then with ASan/UBSan)
#   4. the runtime of each FMI version as a shared library exactly as `cosim build` compiles it
#      (with the tape interpreter); checks the exports (every function of fmi2Functions.h /
#      fmi3Functions.h, nothing else)
#   5. if cmake is available: fmpy's CMake project for each version (plain cc, all warnings, no -lm)
set -eu

here=$(cd "$(dirname "$0")" && pwd)
runtime=$(dirname "$here")
fmi=${FMI2_HEADERS:-$(python3 -c "import fmpy, os; print(os.path.join(os.path.dirname(fmpy.__file__), 'c-code'))")}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
CC=${CC:-gcc}
# the runtime of each FMI version: the core and the version's API
fmi2_rt="$runtime/cosim_runtime.c $runtime/fmi2_api.c"
fmi3_rt="$runtime/cosim_runtime.c $runtime/fmi3_api.c"
warn="-std=c99 -Wall -Wextra -Wpedantic -Werror"
lib="-fPIC -shared -fvisibility=hidden"

# The runtime's core and API objects, compiled once per set of flags ($1, e.g. -O2) and linked
# into the harnesses and the other FMUs below: rt2$2 (core + FMI 2 API), rt3$2 (core + FMI 3 API)
# and rt23$2 (core and both APIs).  $2: file name suffix.
objects() {
    pids=""
    for f in cosim_runtime fmi2_api fmi3_api; do
        $CC $warn $1 -fPIC -fvisibility=hidden -I"$fmi" -I"$runtime" -c "$runtime/$f.c" -o "$out/$f$2.o" &
        pids="$pids $!"
    done
    for pid in $pids; do wait "$pid"; done
    rt2="$out/cosim_runtime$2.o $out/fmi2_api$2.o"
    rt3="$out/cosim_runtime$2.o $out/fmi3_api$2.o"
    rt23="$rt2 $out/fmi3_api$2.o"
}

# The other FMUs of the FMU-state tests (see harness.c and harness3.c): the runtime with another
# model, built like an FMU binary.  $1: extra compiler flags, $2: file name suffix (after objects
# with the same flags).
others() {
    $CC $warn $1 $lib -I"$fmi" -I"$runtime" "$here/test_model_small.c" $rt2 -o "$out/small$2.so" -lm
    $CC $warn $1 $lib -I"$fmi" -I"$runtime" "$here/test_model_small.c" "-DTEST_MODEL_GUID=\"$guid\"" $rt2 \
        -o "$out/small_same_guid$2.so" -lm
    $CC $warn $1 $lib -I"$fmi" -I"$runtime" "$here/test_model.c" "-DTEST_MODEL_GUID=\"$twin_guid\"" $rt2 \
        -o "$out/twin$2.so" -lm
    $CC $warn $1 $lib -I"$fmi" -I"$runtime" "$here/test_model_init.c" $rt2 -o "$out/init$2.so" -lm
    $CC $warn $1 $lib -I"$fmi" -I"$runtime" "$here/test_model_small.c" $rt3 -o "$out/small3$2.so" -lm
    $CC $warn $1 $lib -I"$fmi" -I"$runtime" "$here/test_model.c" "-DTEST_MODEL_GUID=\"$twin_guid\"" $rt3 \
        -o "$out/twin3$2.so" -lm
}
guid='{8c4e810f-3df3-4a00-8276-176fa3c9f000}'      # test_model.c (GUID in harness.c)
twin_guid='{8c4e810f-3df3-4a00-8276-176fa3c9f001}' # TWIN_GUID in harness.c and harness3.c
san="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"

echo "== harness (-O2)"
objects "-O2" ""
others "-O2" ""
$CC $warn -O2 -I"$fmi" -I"$runtime" "$here/harness.c" "$here/test_model.c" $rt2 -o "$out/harness" -lm -ldl
"$out/harness" "$out/small.so" "$out/small_same_guid.so" "$out/twin.so" "$out/init.so"

echo "== FMI 3 harness (-O2)"
$CC $warn -O2 -DTEST_MODEL_ARRAYS -I"$fmi" -I"$runtime" "$here/harness3.c" "$here/test_model.c" $rt23 \
    -o "$out/harness3" -lm -ldl
"$out/harness3" "$out/small3.so" "$out/twin3.so"

echo "== the integrator's step size factor (-O2)"
$CC $warn -O2 -I"$fmi" -I"$runtime" "$here/step_factor.c" "$here/test_model_small.c" -o "$out/step_factor" -lm
"$out/step_factor"

echo "== the tape interpreter (-O2, then -O0 with address and undefined behaviour sanitizers)"
$CC $warn -O2 -I"$runtime" "$here/tape_harness.c" "$runtime/cosim_tape.c" -o "$out/tape" -lm
"$out/tape"
$CC $warn -O0 -g $san -I"$runtime" "$here/tape_harness.c" "$runtime/cosim_tape.c" -o "$out/tape_san" -lm
"$out/tape_san" > "$out/tape_san.log" 2>&1 || { cat "$out/tape_san.log"; exit 1; }
tail -n 1 "$out/tape_san.log"

echo "== harness (-O0, address and undefined behaviour sanitizers)"
objects "-O0 -g $san" "_san"
others "-O0 -g $san" "_san"
$CC $warn -O0 -g $san -I"$fmi" -I"$runtime" "$here/harness.c" "$here/test_model.c" $rt2 \
    -o "$out/harness_san" -lm -ldl
"$out/harness_san" "$out/small_san.so" "$out/small_same_guid_san.so" "$out/twin_san.so" "$out/init_san.so" > "$out/san.log" 2>&1 ||
    { cat "$out/san.log"; exit 1; }
tail -n 1 "$out/san.log"

echo "== FMI 3 harness (-O0, address and undefined behaviour sanitizers)"
$CC $warn -O0 -g $san -DTEST_MODEL_ARRAYS -I"$fmi" -I"$runtime" "$here/harness3.c" "$here/test_model.c" \
    $rt23 -o "$out/harness3_san" -lm -ldl
"$out/harness3_san" "$out/small3_san.so" "$out/twin3_san.so" > "$out/san3.log" 2>&1 ||
    { cat "$out/san3.log"; exit 1; }
tail -n 1 "$out/san3.log"

# The exports of the runtime of FMI version $1 (2 or 3) built as `cosim build` does: exactly the
# functions fmi$1Functions.h declares.
exports() {
    rt=$2
    $CC -std=c99 -O2 $lib -Wall -Wextra -Werror -I"$fmi" -I"$runtime" \
        $rt "$here/test_model.c" -o "$out/model$1.so" -lm
    exports=$(nm -D --defined-only "$out/model$1.so" | awk '$2 == "T" { print $3 }' | sort)
    expected=$(grep -o "FMI$1_Export *fmi$1[A-Za-z0-9]*TYPE *fmi$1[A-Za-z0-9]*" "$fmi/fmi$1Functions.h" |
               awk '{ print $3 }' | sort)
    if [ "$exports" != "$expected" ]; then
        echo "exported symbols differ from the FMI $1 API:"
        echo "$exports" > "$out/a"; echo "$expected" > "$out/b"; diff "$out/a" "$out/b" || true
        exit 1
    fi
    echo "exports: $(echo "$exports" | wc -l) fmi$1 functions, nothing else"
}
echo "== shared library as built by cosim build"
exports 2 "$fmi2_rt $runtime/cosim_tape.c"
exports 3 "$fmi3_rt $runtime/cosim_tape.c"

# fmpy's CMake project for FMI version $1 with the runtime files $2 (;-separated); $3: the libc
# functions the runtime may need.
cmake_build() {
    mkdir -p "$out/cmake$1" "$out/target$1"
    cmake -S "$fmi" -B "$out/cmake$1" -DFMI_MODEL_IDENTIFIER=model -DFMI_ALL_WARNINGS=ON \
        "-DFMI_INCLUDE_DIRS=$runtime" "-DFMI_SOURCES=$2" \
        "-DFMI_TARGET_DIR=$out/target$1" > "$out/cmake$1.log" 2>&1 || { cat "$out/cmake$1.log"; exit 1; }
    # the runtime alone: its own warnings, and no undefined symbols beyond libc and COSIM_MODEL
    cmake --build "$out/cmake$1" > "$out/build$1.log" 2>&1 || { cat "$out/build$1.log"; exit 1; }
    if grep -i "warning" "$out/build$1.log"; then echo "warnings in the CMake build"; exit 1; fi
    undefined=$(nm -u "$out/cmake$1/model.so" | awk '{ print $2 }' | grep -v -e '^COSIM_MODEL$' \
        -e '^__' -e '^_ITM' $(for f in $3; do printf ' -e ^%s' "$f"; done) || true)
    if [ -n "$undefined" ]; then echo "unexpected undefined symbols: $undefined"; exit 1; fi
    echo "FMI $1: builds warning-free; needs only libc ($(echo $3 | sed 's/ /, /g'))"
}
if command -v cmake > /dev/null 2>&1; then
    echo "== fmpy CMake project (cc, FMI_ALL_WARNINGS, no -lm)"
    cmake_build 2 "$runtime/cosim_runtime.c;$runtime/fmi2_api.c" "memcpy memset memcmp strcmp strlen vsnprintf"
    # FMI 3 has no allocator callbacks: the instance memory comes from calloc and free
    cmake_build 3 "$runtime/cosim_runtime.c;$runtime/fmi3_api.c" \
        "memcpy memset memcmp strcmp strlen vsnprintf calloc free"
fi
echo "== all runtime tests passed"
