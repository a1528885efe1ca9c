#!/usr/bin/env bash
# Builds the firmware and runs its on-target tests in QEMU (netduinoplus2, STM32F405): every
# test target (tests/codec.rs, tests/drive.rs, tests/malformed.rs, and tests/signed.rs under
# `-icount shift=0`, so that its timings count instructions). Fails when any target fails or
# does not report; prints flash/RAM figures, each target's stack high-water and the
# verification cost.
set -euo pipefail
cd "$(dirname "$0")"
export CARGO_BUILD_JOBS=${CARGO_BUILD_JOBS:-2}
# The on-target test targets; each reports "stack high-water (<name>): N of M B".
targets=(codec drive malformed signed)
command -v qemu-system-arm >/dev/null || { echo "run-tests.sh: qemu-system-arm missing (Debian: qemu-system-arm)" >&2; exit 1; }
command -v defmt-print >/dev/null || cargo install defmt-print --locked
cargo build --release --features qemu
elf=target/thumbv7em-none-eabihf/release/obu-firmware
echo "== image: $elf"
size -A "$elf" | awk '/^\.(text|rodata|data|bss|uninit|vector_table) /{print; s[$1]=$2}
  END {flash=s[".vector_table"]+s[".text"]+s[".rodata"]+s[".data"]; ram=s[".data"]+s[".bss"]+s[".uninit"];
       printf "flash %d B (%.1f KiB), static RAM %d B (%.1f KiB)\n", flash, flash/1024, ram, ram/1024}'
log=target/on-target-tests.log
# --no-fail-fast: every target runs even after one failed; cargo still exits non-zero then.
if ! cargo test --release --features qemu --no-fail-fast \
  --test codec --test drive --test malformed 2>&1 | tee "$log"; then
  echo "run-tests.sh: ON-TARGET TESTS FAILED (log: obu/firmware/$log)" >&2
  exit 1
fi
# One virtual nanosecond per instruction: the 1 kHz SysTick counts millions of instructions.
if ! QEMU_EXTRA="-icount shift=0" cargo test --release --features qemu --test signed 2>&1 \
  | tee -a "$log"; then
  echo "run-tests.sh: ON-TARGET TESTS FAILED (signed; log: obu/firmware/$log)" >&2
  exit 1
fi
# A target that exited 0 without running its tests would not report: count the reports.
passed=$(grep -c "^all tests passed!" "$log" || true)
missing=()
for t in "${targets[@]}"; do
  grep -q "stack high-water ($t):" "$log" || missing+=("$t")
done
if [ "$passed" -ne "${#targets[@]}" ] || [ "${#missing[@]}" -ne 0 ]; then
  echo "run-tests.sh: expected ${#targets[@]} on-target test targets to pass, $passed did;" \
    "no report from: ${missing[*]:-none} (log: obu/firmware/$log)" >&2
  exit 1
fi
grep -h "high-water\|M instructions" "$log" | sed 's/^/== /'
echo "run-tests.sh: all on-target tests passed (${targets[*]})"
