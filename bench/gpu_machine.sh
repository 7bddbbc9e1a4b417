#!/usr/bin/env bash
# Measures fracref on a machine without a package registry (a lent GPU machine), from a release
# build made on this one: docs/PERFORMANCE.md's GPU section comes from its output.
#
#   bench/gpu_machine.sh pack DIR      here: copies build/fracref, the shared libraries it needs
#                                      that a bare machine may lack, the bunny and the Vulkan unit
#                                      tests into DIR
#   bench/gpu_machine.sh run DIR OUT   there: runs the Vulkan unit tests, the five demos on both
#                                      backends, the kernels, the thread counts and the refine
#                                      phases, and checks that every thread count and backend
#                                      writes the same surface; the results go to OUT
#
# The Vulkan driver must be installed there (its ICD; VK_DRIVER_FILES names it when the loader does
# not find it). REPEAT (default 3) sets the bench's runs of each measurement; SCENES and
# KERNEL_SIZES (defaults: the five demos; 10000,100000,1000000) shorten a trial run.
set -euo pipefail

pack() {
  local dir=$1 root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  local build=${FRACREF_BUILD_DIR:-$root/build}
  [[ -x $build/fracref ]] || { echo "gpu_machine.sh: no $build/fracref: build first" >&2; exit 1; }
  mkdir -p "$dir/lib" "$dir/data" "$dir/tests"
  cp "$build/fracref" "$dir/"
  cp "$build"/tests/vk_*_test "$dir/tests/" 2>/dev/null || true
  cp "$build/data/bunny.obj" "$dir/data/"
  # The libraries outside the C and C++ runtimes, which every Linux has.
  ldd "$build/fracref" | awk '/=> \// {print $3}' | grep -Ev '/lib(c|m|stdc\+\+|gcc_s|pthread|dl|rt)\.so' |
    while read -r lib; do cp -L "$lib" "$dir/lib/"; done
  echo "gpu_machine.sh: packed into $dir ($(du -sh "$dir" | cut -f1))"
}

run() {
  local dir out repeat
  dir=$(cd "$1" && pwd)
  mkdir -p "$2"
  out=$(cd "$2" && pwd)
  repeat=${REPEAT:-3}
  export LD_LIBRARY_PATH="$dir/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
  local f=$dir/fracref
  { nproc; command -v nvidia-smi >/dev/null && nvidia-smi -L; date; } >"$out/machine.txt" 2>&1 || true
  for t in "$dir"/tests/vk_*_test; do [[ -x $t ]] && "$t" --gtest_brief=1 2>&1 | tail -3; done >"$out/vk_tests.txt" 2>&1 || true
  "$f" bench --scenes "${SCENES:-bunny,branch,wall,clay,jello}" --backends cpu,vulkan --repeat "$repeat" --stop-after refine \
    --no-kernels -q --markdown "$out/scenes.md" --json "$out/scenes.json" >>"$out/log.txt" 2>&1
  "$f" bench --kernels-only --backends cpu,vulkan --repeat "$repeat" --kernel-sizes "${KERNEL_SIZES:-10000,100000,1000000}" -q \
    --markdown "$out/kernels.md" >>"$out/log.txt" 2>&1
  "$f" bench --scenes clay,jello --backends cpu --threads 1,4 --repeat "$repeat" --stop-after refine --no-kernels -q \
    --markdown "$out/threads.md" >>"$out/log.txt" 2>&1
  same_surface "$f" "$out"
}

# The clay's refined surface on every hardware thread, on 1 thread and on the Vulkan backend: the
# same bytes (md5) on each.
same_surface() {
  local f=$1 out=$2 scratch
  scratch=$(mktemp -d)
  for b in "cpu" "cpu --threads 1" "vulkan"; do
    # shellcheck disable=SC2086
    "$f" demo clay -o "$scratch/$b" --stop-after refine -q --backend $b >/dev/null 2>&1 || echo "$b: failed"
    echo "$b $(md5sum <"$scratch/$b/fracture_surface.ply" | cut -d' ' -f1)"
  done >"$out/same_surface.txt"
  rm -rf "$scratch"
  cat "$out/same_surface.txt"
}

case ${1:-} in
  pack) [[ $# -eq 2 ]] || { echo "usage: $0 pack DIR" >&2; exit 2; }; pack "$2" ;;
  run) [[ $# -eq 3 ]] || { echo "usage: $0 run DIR OUT" >&2; exit 2; }; run "$2" "$3" ;;
  *) echo "usage: $0 pack DIR | run DIR OUT" >&2; exit 2 ;;
esac
