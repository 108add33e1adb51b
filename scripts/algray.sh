#!/usr/bin/env bash
# The two commands of the README:
#   bash scripts/algray.sh render   install what is missing, build, render the default scene
#   bash scripts/algray.sh test     install what is missing, build, run every test
#                                   (Release, ASan+UBSan, -march=native, Clang, then the
#                                   installed-package consumers examples/minimal and
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
# The test command also builds with Clang (a second compiler's warnings and code).
if [[ ${1:-} == test ]]; then packages+=(clang-14); fi
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
    # ASan + UBSan build of the test suites (benchmarks excluded: they are timing code),
    # at -O1 with line tables (-g1: file and line in every report), the level the
    # AddressSanitizer documentation suggests. Measured (session 20, Zen 3 host): against
    # RelWithDebInfo's -O2 -g, roots_yuksel.cpp compiled in 65 s instead of 207 s and the
    # whole build in 9 min on one core instead of 15 min on two; the same tests ran 1.1x
    # as long (210 s against 190 s of test time).
    configure_and_build build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DALGRAY_SANITIZE=ON \
      -DALGRAY_BUILD_BENCHMARKS=OFF "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG"
    ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
      ctest --test-dir build-asan --output-on-failure -j "$jobs"
    # The host's own instruction set (FMA where the CPU has it, as a user's -march=native
    # build): the bit-identity and error-bound tests must hold there too (the library
    # builds with -ffp-contract=off, CMakeLists.txt).
    configure_and_build build-native -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-march=native \
      -DALGRAY_BUILD_BENCHMARKS=OFF
    ctest --test-dir build-native --output-on-failure -j "$jobs"
    # Clang 14 (benchmarks included, so that they build there too): the same warnings as
    # errors, and the same bits (the bit-identity tests compare the ISAs' kernels, which
    # Clang compiles per function as GCC does, plugin/core/isa_target.h).
    configure_and_build build-clang -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14
    ctest --test-dir build-clang --output-on-failure -j "$jobs"
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
