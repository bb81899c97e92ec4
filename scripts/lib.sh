# Shared by scripts/run and scripts/test: install what is missing, configure, build.
# Sourced, not run. Idempotent: a second call with nothing changed does no work.
set -euo pipefail

SINEW_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SINEW_JOBS=${SINEW_JOBS:-2}

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

# install_packages ROLE...: the packages of packages.txt needed for those roles.
install_packages() {
  local roles=" $* " wanted=() missing=() name role
  while read -r name role _; do
    [ -z "$name" ] && continue
    case "$name" in \#*) continue ;; esac
    [[ "$roles" == *" $role "* ]] && wanted+=("$name")
  done < "$SINEW_ROOT/scripts/packages.txt"
  for name in "${wanted[@]}"; do
    dpkg-query -W -f='${Status}' "$name" 2>/dev/null | grep -q "install ok installed" ||
      missing+=("$name")
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "== installing ${missing[*]}"
    as_root apt-get update -q
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -q --no-install-recommends \
      "${missing[@]}"
  fi
  # Debian's nodejs has no npm; NodeSource's bundles it (and conflicts with Debian's npm).
  if [[ "$roles" == *" test "* ]] && ! command -v npm >/dev/null; then
    DEBIAN_FRONTEND=noninteractive as_root apt-get install -y -q --no-install-recommends npm
  fi
}

# install_node_tools: the Khronos glTF validator, pinned by tools/package-lock.json.
install_node_tools() {
  local stamp="$SINEW_ROOT/tools/node_modules/.package-lock.json"
  if [ ! -f "$stamp" ] || [ "$SINEW_ROOT/tools/package-lock.json" -nt "$stamp" ]; then
    echo "== installing the glTF validator (npm ci in tools/)"
    npm ci --prefix "$SINEW_ROOT/tools" --no-audit --no-fund --loglevel=error
  fi
}

# build DIR CMAKE_ARGS...: configure (first time, or when args change) and build.
build() {
  local dir="$SINEW_ROOT/$1"
  shift
  # ccache keyed on paths relative to the checkout, so another clone of the same sources (CI's)
  # reuses this machine's cache.
  export CCACHE_BASEDIR="$SINEW_ROOT" CCACHE_NOHASHDIR=true
  local launcher=()
  command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  cmake -S "$SINEW_ROOT" -B "$dir" -G Ninja "${launcher[@]}" "$@" >/dev/null
  echo "== building $dir"
  cmake --build "$dir" -j "$SINEW_JOBS"
}
