# Sourced (not run) by the entry scripts (render_default.sh, test.sh, bench.sh), from the
# repository root: install what is missing, build, and keep the kernel caches inside the build
# tree (PoCL's own, and archwave's cache of compiled programs for runtimes without one,
# host/cl/kernel_cache.h), so tests, CI steps and renders reuse compiled kernels. One place
# for all three.
bash scripts/setup.sh
bash scripts/build.sh
export POCL_CACHE_DIR="$PWD/build/pocl-cache"
export ARCHWAVE_KERNEL_CACHE="${ARCHWAVE_KERNEL_CACHE:-$PWD/build/kernel-cache}"
mkdir -p "$POCL_CACHE_DIR"
