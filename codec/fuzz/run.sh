#!/usr/bin/env bash
# Fuzzes the codec with cargo-fuzz (libFuzzer, nightly): builds the seed corpus (seed.sh),
# builds the targets, runs each for SECONDS, prints the executions per target, and fails
# when a target crashed (a panic, a violated invariant, a timeout or running out of memory).
# Without a nightly toolchain it prints why and exits 0 (skipped), except under CI=true,
# where a missing nightly fails the run.
#
# Usage: codec/fuzz/run.sh SECONDS [TARGET...]   (default targets: message_frame jer envelope gnss)
# Environment:
#   FUZZ_SANITIZER   cargo-fuzz sanitizer, default `none` (the codec forbids `unsafe`; without
#                    ASan a target runs 5-15 times more inputs per second). `address` works too,
#                    but switching rebuilds everything (one target dir for both).
#   FUZZ_SHARED_DIR  the shared data for the seed corpus, default ../shared beside the repo.
#   FUZZ_ARGS        more libFuzzer options for every target (e.g. -seed=1).
#   FUZZ_JOBS        targets fuzzed at a time, default the number of cores.
#   FUZZ_FEATURES    features of the fuzz crate, e.g. `alloc` (heap storage); built in its
#                    own target dir (codec/fuzz/target-<features>).
# Crashes are saved in codec/fuzz/artifacts/<target>/, logs in codec/fuzz/logs/ (git-ignored).
# Reproduce one: cd codec && cargo +nightly fuzz run -a -s none <target> <artifact file>
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
codec=$(dirname "$here")
secs=${1:-}
[[ $secs =~ ^[0-9]+$ && $secs -gt 0 ]] || { echo "usage: $0 SECONDS [TARGET...]" >&2; exit 2; }
shift
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(message_frame jer envelope gnss)
sanitizer=${FUZZ_SANITIZER:-none}
read -r -a extra_args <<<"${FUZZ_ARGS:-}"
build_args=(-a -s "$sanitizer")
if [[ -n ${FUZZ_FEATURES:-} ]]; then
    build_args+=(--features "$FUZZ_FEATURES" --target-dir "$here/target-${FUZZ_FEATURES//[^a-z0-9]/-}")
fi

if ! nightly=$(cargo +nightly --version 2>&1); then
    why="no nightly toolchain ('cargo +nightly --version' failed: ${nightly//$'\n'/ })"
    # CI machines have nightly: there a missing one is a broken gate, not a skip.
    if [[ ${CI:-} == true ]]; then
        echo "=== fuzzing FAILED: $why (CI=true needs it: rustup toolchain install nightly)" >&2
        exit 1
    fi
    echo "=== fuzzing SKIPPED: $why"
    exit 0
fi
echo "fuzzing with $nightly, sanitizer $sanitizer${FUZZ_FEATURES:+, features $FUZZ_FEATURES}, ${secs}s per target: ${targets[*]}"
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    echo "cargo-fuzz is missing: cargo install cargo-fuzz --locked"
    cargo install cargo-fuzz --locked || { echo "cannot install cargo-fuzz" >&2; exit 1; }
fi
bash "$here/seed.sh" ${FUZZ_SHARED_DIR:+"$FUZZ_SHARED_DIR"} || { echo "seed.sh failed" >&2; exit 1; }

cd "$codec" || exit 1
export CARGO_BUILD_JOBS=${CARGO_BUILD_JOBS:-2}
# Release with debug assertions and overflow checks (-a): an arithmetic overflow is a crash.
cargo +nightly fuzz build "${build_args[@]}" || { echo "building the fuzz targets failed" >&2; exit 1; }

mkdir -p "$here/logs"
# One libFuzzer process is one thread: the targets run side by side, as many at a time as the
# machine has cores (FUZZ_JOBS), each for its full SECONDS.
jobs=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 1)}
fuzz_one() {
    local t=$1 log=$here/logs/$1.log dict=()
    [[ $t == jer && -f $here/corpus/jer.dict ]] && dict=("-dict=$here/corpus/jer.dict")
    cargo +nightly fuzz run "${build_args[@]}" "$t" -- \
        -max_total_time="$secs" -print_final_stats=1 -timeout=10 -rss_limit_mb=2048 \
        ${dict[@]+"${dict[@]}"} ${extra_args[@]+"${extra_args[@]}"} >"$log" 2>&1
    echo $? >"$here/logs/$t.rc"
}
running=0
for t in "${targets[@]}"; do
    echo "--- $t: ${secs}s (log: ${here#"$codec"/}/logs/$t.log)"
    rm -f "$here/logs/$t.rc"
    fuzz_one "$t" &
    running=$((running + 1))
    if [[ $running -ge $jobs ]]; then
        wait -n
        running=$((running - 1))
    fi
done
wait
total=0
failed=()
for t in "${targets[@]}"; do
    log=$here/logs/$t.log
    rc=$(cat "$here/logs/$t.rc" 2>/dev/null || echo 1)
    execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$')
    if [[ $rc -ne 0 || -z $execs ]]; then
        failed+=("$t")
        echo "$t: FAILED (exit $rc) after ${execs:-?} executions"
        grep -E -A3 "panicked at|ERROR: libFuzzer|SUMMARY|Test unit written|error(\[|:)" "$log" | head -n 40
    else
        total=$((total + execs))
        rate=$(grep -o 'exec/s: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*$')
        cov=$(grep -E '^#[0-9]+[[:space:]]+DONE' "$log" | grep -o 'cov: [0-9]*' | tail -n 1)
        echo "$t: $execs executions (${rate:-?} exec/s, ${cov:-cov: ?}), no crash"
    fi
done
echo "=== fuzzing: $total executions in total over ${#targets[@]} target(s)"
if [[ ${#failed[@]} -gt 0 ]]; then
    echo "=== fuzzing FAILED: ${failed[*]} (artifacts in ${here#"$codec"/}/artifacts/)"
    exit 1
fi
