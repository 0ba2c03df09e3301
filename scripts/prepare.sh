# Sourced (not run) by the entry scripts (render_default.sh, test.sh, bench.sh), from the
# repository root: install what is missing, build, and keep PoCL's kernel cache inside the
# build tree, so tests, CI steps and renders reuse compiled kernels. One place for all three.
bash scripts/setup.sh
bash scripts/build.sh
export POCL_CACHE_DIR="$PWD/build/pocl-cache"
mkdir -p "$POCL_CACHE_DIR"
