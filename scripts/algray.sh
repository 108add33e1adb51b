#!/usr/bin/env bash
# The two commands of the README:
#   bash scripts/algray.sh render   install what is missing, build, render the default scene
#   bash scripts/algray.sh test     install what is missing, build, run every test
#                                   (GCC Release; Clang with ASan+UBSan and -march=native;
#                                   then the installed-package consumers examples/minimal and
#                                   tests/package/core_only against a temporary prefix,
#                                   static and shared)
set -euo pipefail
usage() {
  echo "usage: bash scripts/algray.sh render|test" >&2
  exit 2
}
# The argument first: a typo ("rendr") installed some 20 packages before the usage line.
case "${1:-}" in
  render | test) ;;
  *) usage ;;
esac
cd "$(dirname "$0")/.."
root=$(pwd)
jobs=$(nproc 2>/dev/null || echo 2)

# ---- 1. Debian bookworm packages ------------------------------------------------
packages=(cmake ninja-build g++ pkg-config libembree-dev libopenimageio-dev openimageio-tools
          libglm-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev libmpfr-dev
          libgmp-dev nlohmann-json3-dev libtinyobjloader-dev libcli11-dev python3
          python3-matplotlib povray clang-format)
# The test command also builds with Clang (a second compiler's warnings and code), with
# its sanitizer runtimes (libclang-rt-14-dev; without it the link fails).
if [[ ${1:-} == test ]]; then packages+=(clang-14 libclang-rt-14-dev); fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "algray: installing ${missing[*]}"
  sudo_cmd=()
  [[ $(id -u) -ne 0 ]] && sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -q
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

configure_and_build() {  # dir, extra cmake args...
  local dir=$1; shift
  cmake -S "$root" -B "$dir" -G Ninja "$@"
  cmake --build "$dir" -j "$jobs"
}

case "${1:-}" in
  render)
    configure_and_build build -DCMAKE_BUILD_TYPE=Release
    build/examples/render/algray-render -o algray.png "${@:2}"
    ;;
  test)
    # Release build: unit tests, stress tests and one smoke run of every benchmark.
    configure_and_build build -DCMAKE_BUILD_TYPE=Release
    ctest --test-dir build --output-on-failure -j "$jobs"
    # Clang 14 with ASan + UBSan and the host's own instruction set, one build for what
    # were three (a GCC sanitizer build, a GCC -march=native build and a Clang Release
    # build, which took CI to 42 minutes on 2 cores): a second compiler's warnings as
    # errors and code; the sanitizers over every suite and tool; and the bit-identity and
    # error-bound tests on FMA/AVX2 where the CPU has them, as a user's -march=native build
    # has them (the library builds with -ffp-contract=off, CMakeLists.txt: with GCC's
    # default contraction 4 test programs failed so). At -O1 with line tables (-g1: file
    # and line in every report), the level the AddressSanitizer documentation suggests
    # (session 20: -O2 -g compiled roots_yuksel.cpp in 207 s against 65 s). Benchmarks
    # are excluded (timing code; the Release build builds and runs them). Left to the
    # Release run: the Embree suites' second run on Embree's SSE2 kernels (*.EmbreeSse2:
    # Embree's code differs there, algray's does not), the core suites' second run on the
    # baseline kernels (*.CoreSse2: core_isa_test runs those kernels beside the AVX2 ones
    # here) and most of the MPFR root fuzzing (500 of its 2500 problems per precision).
    configure_and_build build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DALGRAY_SANITIZE=ON \
      -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_CXX_FLAGS=-march=native \
      -DALGRAY_BUILD_BENCHMARKS=OFF "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ALGRAY_ROOTS_FUZZ_PROBLEMS=500 \
      ctest --test-dir build-asan --output-on-failure -j "$jobs" -E '[.](EmbreeSse2|CoreSse2)$'
    # The installed package: find_package(algray) from examples/minimal, and a consumer of
    # the math core alone (tests/package/core_only) with Embree hidden, which it must not
    # need. Then the same with shared libraries (BUILD_SHARED_LIBS=ON, the libraries only:
    # no tests, benchmarks or tools; this stage measured 69 s on 2 shared cores, 67 s of it
    # the shared build and its consumers).
    build_consumers() {  # prefix
      local prefix=$1
      cmake -S examples/minimal -B "$prefix/minimal-build" -G Ninja \
        -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release
      cmake --build "$prefix/minimal-build" -j "$jobs"
      "$prefix/minimal-build/algray-minimal"
      cmake -S tests/package/core_only -B "$prefix/core-only-build" -G Ninja \
        -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON
      # (CMake's warning that CMAKE_DISABLE_FIND_PACKAGE_embree was not used is the point.)
      cmake --build "$prefix/core-only-build" -j "$jobs"
      "$prefix/core-only-build/algray-core-only"
    }
    prefix=$(mktemp -d)
    cmake --install build --prefix "$prefix" >/dev/null
    build_consumers "$prefix"
    rm -rf "$prefix"
    configure_and_build build-shared -DCMAKE_BUILD_TYPE=Release -DBUILD_SHARED_LIBS=ON \
      -DALGRAY_BUILD_TESTS=OFF -DALGRAY_BUILD_BENCHMARKS=OFF -DALGRAY_BUILD_EXAMPLES=OFF
    prefix=$(mktemp -d)
    cmake --install build-shared --prefix "$prefix" >/dev/null
    for lib in algray_core algray; do
      if ! compgen -G "$prefix/lib*/lib$lib.so.*" >/dev/null; then
        echo "algray: BUILD_SHARED_LIBS=ON installed no shared lib$lib" >&2
        exit 1
      fi
    done
    build_consumers "$prefix"
    rm -rf "$prefix"
    ;;
  *)
    usage
    ;;
esac
