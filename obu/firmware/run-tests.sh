#!/usr/bin/env bash
# Builds the firmware and runs its on-target tests in QEMU (netduinoplus2, STM32F405).
# Fails loudly on the first failing test; prints flash/RAM figures and the stack high-water.
set -euo pipefail
cd "$(dirname "$0")"
export CARGO_BUILD_JOBS=${CARGO_BUILD_JOBS:-2}
command -v qemu-system-arm >/dev/null || { echo "run-tests.sh: qemu-system-arm missing (Debian: qemu-system-arm)" >&2; exit 1; }
command -v defmt-print >/dev/null || cargo install defmt-print --locked
cargo build --release --features qemu
elf=target/thumbv7em-none-eabihf/release/obu-firmware
echo "== image: $elf"
size -A "$elf" | awk '/^\.(text|rodata|data|bss|uninit|vector_table) /{print; s[$1]=$2}
  END {flash=s[".vector_table"]+s[".text"]+s[".rodata"]+s[".data"]; ram=s[".data"]+s[".bss"]+s[".uninit"];
       printf "flash %d B (%.1f KiB), static RAM %d B (%.1f KiB)\n", flash, flash/1024, ram, ram/1024}'
if ! cargo test --release --features qemu 2>&1 | tee target/on-target-tests.log; then
  echo "run-tests.sh: ON-TARGET TESTS FAILED (log: obu/firmware/target/on-target-tests.log)" >&2
  exit 1
fi
grep -h "high-water" target/on-target-tests.log | sed 's/^/== /' || true
echo "run-tests.sh: all on-target tests passed"
