# shellcheck shell=bash
# The Debian 12 packages slipfront needs, and ensure_deps to install the missing ones.
# Sourced by scripts/build.sh (and through it by test.sh, test_slow.sh, main.sh):
#   source scripts/deps.sh && ensure_deps
# No `set -euo pipefail` here: a sourced file would change the options of the shell that sources it;
# the calling scripts set them.

# What the program and the main job need (scripts/main.sh installs only these: build.sh --program-only) ...
SLIPFRONT_DEPS_PROGRAM=(
  build-essential cmake ninja-build git      # toolchain
  libeigen3-dev libboost-random-dev          # numerics, reproducible random streams
  libhdf5-dev libtomlplusplus-dev libcli11-dev  # results file, configs, command line
  libxxhash-dev pkg-config                   # checksums of checkpoints and run files
  libfftw3-dev                               # the strip's cosine transform
  python3-matplotlib python3-h5py python3-numpy  # scripts/plot.py
)
# ... and what the tests and benchmarks add (125 more packages on a fresh machine: SUNDIALS brings Open MPI and
# gfortran; ~11 s of apt-get there, measured by reinstalling them, docs/performance.md §17; the two Python lines add 12
# packages, measured on this machine with apt-get install)
SLIPFRONT_DEPS_TESTS=(
  catch2 libbenchmark-dev                    # tests, benchmarks
  libsundials-dev                            # reference ODE integrator
  libopenmpi-dev openmpi-bin                 # optional at run time: studies on MPI (mpirun -n K slipfront study)
  pybind11-dev python3-pytest python3-xarray # the Python package (docs/python.md): in-process module, its tests
  python3-tqdm python3-pandas                # ... its optional progress bars and tables (tests skip without them)
)
# The packages ensure_deps installs (scripts may narrow or extend it first, e.g. build.sh --program-only, fuzz.sh).
SLIPFRONT_DEPS=("${SLIPFRONT_DEPS_PROGRAM[@]}" "${SLIPFRONT_DEPS_TESTS[@]}")

# Whether every package named as an argument is installed.
installed() {
  local p
  for p in "$@"; do
    [[ "$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)" == "install ok installed" ]] || return 1
  done
}

# The packages of SLIPFRONT_DEPS that are not installed, one per line.
missing_deps() {
  local p
  for p in "${SLIPFRONT_DEPS[@]}"; do
    installed "$p" || echo "$p"
  done
}

# Install whatever is missing (one apt-get update, one apt-get install); a no-op when all are there.
ensure_deps() {
  if ! command -v dpkg-query >/dev/null 2>&1; then
    echo "slipfront: dpkg-query not found: the scripts expect Debian 12 (install the equivalent of:" >&2
    echo "  ${SLIPFRONT_DEPS[*]})" >&2
    return 1
  fi
  local missing
  mapfile -t missing < <(missing_deps)
  if ((${#missing[@]} == 0)); then
    return 0
  fi
  echo "slipfront: missing Debian packages: ${missing[*]}" >&2
  if ((EUID != 0)); then
    echo "slipfront: installing them needs root. Run this script as root, or first:" >&2
    echo "  sudo apt-get update && sudo apt-get install -y --no-install-recommends ${missing[*]}" >&2
    return 1
  fi
  apt-get update
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
  mapfile -t missing < <(missing_deps)
  if ((${#missing[@]} != 0)); then
    echo "slipfront: still missing after apt-get install: ${missing[*]}" >&2
    return 1
  fi
}
