#!/usr/bin/env bash
# stcweave developer entry point.
#   ./dev.sh run   install what is missing, build the stcweave program only (Release, in
#                  build/), mesh data/lblock.obj
#   ./dev.sh test  install what is missing, build everything (tests, benchmarks), run the
#                  whole test suite (ctest; installs chromium for the browser tests); the
#                  reason of every skipped test is printed
#   ./dev.sh build install what is missing, build
#   ./dev.sh lint  also install clang-format and clang-tidy; check the formatting of every
#                  C++ file and run clang-tidy (.clang-tidy) on the libraries and the CLI
# Idempotent: a machine that already has everything only builds.
set -euo pipefail
cd "$(dirname "$0")"

PACKAGES=(cmake g++ make pkg-config libboost-graph-dev libeigen3-dev nlohmann-json3-dev
  libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev liblbfgspp-dev
  libgmsh-dev libjs-three)
BUILD_DIR=${STCWEAVE_BUILD_DIR:-build}
JOBS=${STCWEAVE_JOBS:-$(nproc 2>/dev/null || echo 2)}

install_missing() {
  local missing=()
  for p in "${PACKAGES[@]}" "$@"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ ${#missing[@]} -eq 0 ]; then return 0; fi
  echo "dev.sh: installing missing Debian packages: ${missing[*]}"
  local sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then sudo="sudo"; else
      echo "dev.sh: not root and no sudo: install these packages by hand: ${missing[*]}" >&2
      exit 1
    fi
  fi
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

configure() {
  install_missing "$@"
  if [ ! -f "$BUILD_DIR/CMakeCache.txt" ]; then
    cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release
  fi
}

build() {
  configure "$@"
  cmake --build "$BUILD_DIR" -j "$JOBS"
}

# ctest prints "***Skipped" without the reason, which only the test binary prints: list
# every skipped test with the message GoogleTest gave (the line after "Skipped").
print_skip_reasons() {
  local log=Testing/Temporary/LastTest.log
  [ -f "$log" ] || return 0
  awk '
    /: Skipped$/ { getline reason; pending = reason; next }
    /^\[  SKIPPED \] / && pending != "" {
      name = $4; sub(/ \(.*/, "", name)
      if (!(name in seen)) { seen[name] = 1; printf "  %s: %s\n", name, pending; n++ }
      pending = ""
    }
    END { if (n > 0) printf "dev.sh: %d test(s) skipped, with their reasons above\n", n }
  ' "$log" | { IFS= read -r first || exit 0; echo "dev.sh: skipped tests:"; echo "$first"; cat; }
}

cmd=${1:-}
case "$cmd" in
  build)
    build ;;
  run)
    configure
    cmake --build "$BUILD_DIR" -j "$JOBS" --target stcweave
    mkdir -p "$BUILD_DIR/out"
    echo "dev.sh: meshing the bundled CAD part data/plate_slot.step (needs libgmsh-dev)"
    "$BUILD_DIR/bin/stcweave" mesh data/plate_slot.step -o "$BUILD_DIR/out/plate_slot.vtk" \
      --size 0.25 --report "$BUILD_DIR/out/plate_slot.report.json" ;;
  test)
    build chromium  # headless Chromium for the browser page's tests (ctest label browser)
    cd "$BUILD_DIR"
    status=0
    ctest --output-on-failure -j "$JOBS" || status=$?
    print_skip_reasons
    exit "$status" ;;
  lint)
    build clang-format clang-tidy
    status=0
    if ! git ls-files '*.cpp' '*.hpp' | xargs clang-format --dry-run --Werror; then
      echo "dev.sh: formatting differs: run clang-format -i on the files above" >&2
      status=1
    fi
    run-clang-tidy -p "$BUILD_DIR" -j "$JOBS" -quiet 'stc/src|weave/src|primal/src|cli/' \
      > "$BUILD_DIR/clang-tidy.log" 2>&1 || status=1
    if grep -q "warning:" "$BUILD_DIR/clang-tidy.log"; then
      grep "warning:" "$BUILD_DIR/clang-tidy.log" | sort -u >&2
      status=1
    fi
    [ "$status" -eq 0 ] && echo "dev.sh: clang-format and clang-tidy are clean"
    exit "$status" ;;
  *)
    echo "usage: ./dev.sh run|test|build|lint" >&2
    exit 1 ;;
esac
