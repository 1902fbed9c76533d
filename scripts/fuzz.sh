#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang + ASan + UBSan) into build-fuzz/ and runs each for a
# while on a temporary copy of its seed corpus; exits non-zero on any finding (fuzz/README.md).
# Usage: scripts/fuzz.sh [--seconds N] [--target NAME]... [--jobs J] [--no-install] [--build-dir DIR]
#                        [--corpus-out DIR] [--no-build] [--build-only] [--smoke]
#                        [-- EXTRA_LIBFUZZER_FLAGS...]
#   --seconds N      fuzzing time per target and job (default 30)
#   --smoke          the CI smoke run (scripts/test.sh): deterministic. Each target runs a fixed
#                    number of inputs (smoke_runs below, ~20-40 s here) from libFuzzer's -seed=1 on
#                    one job, so a clean commit gives the same inputs on every run and a CI result
#                    never depends on luck; --seconds is then only a cap for slow machines (a
#                    target stopped by it reports so). Finding new bugs is the job of long runs
#                    without --smoke (random seeds), whose findings become regression inputs.
#   --target NAME    gltf, scene_file, pipeline or image (fuzz_ prefix optional); repeatable; default all
#   --jobs J         parallel fuzzer processes per target, sharing its corpus (default 1)
#   --corpus-out DIR copy each target's grown corpus to DIR/<target>/ afterwards (for fuzz/README.md
#                    "Keeping corpus growth"); the repository's fuzz/corpus is never written
#   --no-install     do not install missing Debian packages
# Before fuzzing, every file in fuzz/regressions/<target>/ is run once (a finding fixed must stay
# fixed). Crash inputs are kept in <build-dir>/artifacts/<run>/ and their paths printed.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
seconds=30
jobs=1
install=1
build=1
build_only=0
smoke=0
build_dir=build-fuzz
corpus_out=""
targets=()
extra=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) seconds="$2"; shift ;;
    --target) t="${2#fuzz_}"; targets+=("$t"); shift ;;
    --jobs) jobs="$2"; shift ;;
    --no-install) install=0 ;;
    --no-build) build=0 ;;
    --build-only) build_only=1 ;;
    --smoke) smoke=1 ;;
    --build-dir) build_dir="$2"; shift ;;
    --corpus-out) corpus_out="$2"; shift ;;
    --) shift; extra=("$@"); break ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "fuzz.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done
all_targets=(gltf scene_file pipeline image live_message)
[ ${#targets[@]} -eq 0 ] && targets=("${all_targets[@]}")
for t in "${targets[@]}"; do
  case " ${all_targets[*]} " in *" $t "*) ;; *) echo "fuzz.sh: unknown target '$t' (${all_targets[*]})" >&2; exit 2 ;; esac
done
case "$seconds$jobs" in *[!0-9]*) echo "fuzz.sh: --seconds and --jobs take whole numbers" >&2; exit 2 ;; esac

# Per target: the longest input, in bytes (seeds are below it: scripts/make_fuzz_corpus.sh).
max_len() {
  case "$1" in
    gltf) echo 65536 ;; image) echo 65536 ;; *) echo 16384 ;;
  esac
}

# Per target: the inputs of a --smoke run (about 20-40 s each under ASan on the 2-core machine;
# docs/testing.md). Fixed counts, not time, so the run is the same on any machine.
smoke_runs() {
  case "$1" in
    gltf) echo 30000 ;; scene_file) echo 40000 ;; pipeline) echo 100000 ;; image) echo 5000 ;; live_message) echo 100000 ;;
  esac
}
if [ "$smoke" = 1 ]; then
  [ "$jobs" = 1 ] || { echo "fuzz.sh: --smoke runs one job per target" >&2; exit 2; }
fi

# --- packages (idempotent, as scripts/setup.sh) ----------------------------------------------------
pkgs=(clang libclang-rt-14-dev cmake ninja-build pkg-config
      libglm-dev libtinygltf-dev libopenimageio-dev libtbb-dev nlohmann-json3-dev libssl-dev libdeflate-dev libisal-dev libjpeg62-turbo-dev libpng-dev
      libboost-dev)
[ "$install" = 1 ] && bash scripts/install_packages.sh fuzz.sh "${pkgs[@]}"

# --- build (only the fuzz targets and the libraries they link) ---------------------------------------
if [ "$build" = 1 ]; then
  if [ ! -f "$build_dir/CMakeCache.txt" ]; then
    gen=()
    command -v ninja >/dev/null && gen=(-G Ninja)
    # As scripts/sanitize.sh configures the same folder (the Python module's position-independent
    # libraries): configured alike, the tests' reconfigure rebuilds nothing.
    python=OFF; [ -f /usr/lib/cmake/pybind11/pybind11Config.cmake ] && python=ON
    CC=clang CXX=clang++ cmake -S . -B "$build_dir" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DAQ_BUILD_FUZZ=ON -DBUILD_TESTING=OFF -DAQ_BUILD_BENCH=OFF -DAQ_BUILD_REFERENCE=OFF -DAQ_BUILD_PYTHON=$python >/dev/null
  fi
  build_targets=()
  for t in "${targets[@]}"; do build_targets+=(--target "fuzz_$t"); done
  cmake --build "$build_dir" "${build_targets[@]}" --parallel "$(nproc)"
fi

[ "$build_only" = 1 ] && exit 0

# --- run ---------------------------------------------------------------------------------------------
run_id=$(date +%Y%m%d-%H%M%S)-$$
artifacts="$root/$build_dir/artifacts/$run_id"
work=$(mktemp -d "${TMPDIR:-/tmp}/aq-fuzz-run.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$artifacts" "$work/tmp"
failed=()
# Leaks inside third-party libraries only (each named with its reason in the file).
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
stat_of() { grep -h "^stat::$1:" "$2" 2>/dev/null | awk '{s += $2} END {print s + 0}'; }

for t in "${targets[@]}"; do
  bin="$root/$build_dir/fuzz/fuzz_$t"
  [ -x "$bin" ] || { echo "fuzz.sh: $bin not built" >&2; exit 1; }
  flags=(-rss_limit_mb=2048 -timeout=10 -max_len="$(max_len "$t")" -print_final_stats=1)
  [ -f "fuzz/dict/$t.dict" ] && flags+=(-dict="$root/fuzz/dict/$t.dict")
  # Regressions first: each input once.
  if compgen -G "fuzz/regressions/$t/*" >/dev/null; then
    if ! TMPDIR="$work/tmp" "$bin" "${flags[@]}" -artifact_prefix="$artifacts/$t-regression-" \
           fuzz/regressions/"$t"/* >"$work/$t-regressions.log" 2>&1; then
      echo "fuzz.sh: $t: a regression input fails again (fuzz/regressions/$t/); log:"
      tail -40 "$work/$t-regressions.log"
      failed+=("$t (regression)")
      continue
    fi
    echo "fuzz.sh: $t: $(ls fuzz/regressions/"$t" | wc -l) regression inputs pass"
  fi
  corpus="$work/corpus/$t"
  mkdir -p "$corpus"
  cp fuzz/corpus/"$t"/* "$corpus"/ 2>/dev/null || true
  before=$(ls "$corpus" | wc -l)
  run_flags=(-max_total_time="$seconds")
  if [ "$smoke" = 1 ]; then
    run_flags+=(-seed=1 -runs="$(smoke_runs "$t")" -reload=0 -use_cmp=0 -use_memmem=0)
    echo "fuzz.sh: $t: smoke run of $(smoke_runs "$t") inputs from seed 1 and $before seeds (cap ${seconds}s)"
  else
    echo "fuzz.sh: $t: fuzzing ${seconds}s x $jobs job(s) from $before seeds"
  fi
  # A smoke run gets a fixed folder for the files its target writes (fuzz/fuzz_common.cpp
  # AQ_FUZZ_DIR), the same on every run of this checkout.
  fixed_dir=""
  if [ "$smoke" = 1 ]; then
    fixed_dir="$root/$build_dir/smoke-files/$t"
    rm -rf "$fixed_dir"
  fi
  pids=()
  for j in $(seq 1 "$jobs"); do
    AQ_FUZZ_DIR="$fixed_dir" TMPDIR="$work/tmp" "$bin" "${flags[@]}" "${run_flags[@]}" \
      -artifact_prefix="$artifacts/$t-" "${extra[@]}" "$corpus" >"$work/$t-$j.log" 2>&1 &
    pids+=($!)
  done
  rc=0
  for p in "${pids[@]}"; do wait "$p" || rc=1; done
  logs=("$work/$t"-[0-9]*.log)
  mkdir -p "$artifacts/logs"
  cp "${logs[@]}" "$artifacts/logs/" 2>/dev/null || true
  execs=$(stat_of number_of_executed_units "${logs[@]}")
  rss=$(grep -h "^stat::peak_rss_mb:" "${logs[@]}" | awk '{m = $2 > m ? $2 : m} END {print m + 0}')
  after=$(ls "$corpus" | wc -l)
  rate=$(stat_of average_exec_per_sec "${logs[@]}")
  echo "fuzz.sh: $t: $execs runs (up to ${seconds}s x $jobs job(s); $rate exec/s in all), corpus $before -> $after, peak RSS ${rss} MB"
  if [ "$smoke" = 1 ] && [ "$execs" -lt "$(smoke_runs "$t")" ] && [ "$rc" = 0 ]; then
    echo "fuzz.sh: $t: the ${seconds}s cap stopped the smoke run after $execs of $(smoke_runs "$t") inputs (a slow machine; not a finding)"
  fi
  if [ -n "$corpus_out" ]; then
    mkdir -p "$corpus_out/$t"
    cp -n "$corpus"/* "$corpus_out/$t"/ 2>/dev/null || true
  fi
  if [ "$rc" != 0 ] || compgen -G "$artifacts/$t-*" >/dev/null; then
    failed+=("$t")
    for log in "${logs[@]}"; do
      if grep -qE "ERROR: |==[0-9]+==|Test unit written|aq fuzz: .* threw" "$log"; then
        echo "---- $log"
        grep -E "ERROR: |SUMMARY|aq fuzz: .* threw|Test unit written|#[0-9]+ 0x" "$log" | head -30
      fi
    done
    for a in "$artifacts/$t"-*; do
      [ -e "$a" ] && echo "fuzz.sh: $t: finding kept in $a (reproduce: $bin $a)"
    done
  fi
done

if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz.sh: FINDINGS in: ${failed[*]} (inputs and logs in $artifacts/)"
  exit 1
fi
echo "fuzz.sh: no findings (${targets[*]}; logs in $artifacts/)"
