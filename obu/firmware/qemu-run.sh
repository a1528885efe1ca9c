#!/usr/bin/env bash
# Cargo runner: runs an ELF in QEMU's netduinoplus2 (STM32F405) and decodes its defmt logs.
# Exit status: the firmware's semihosting exit code (0 = tests passed). Extra QEMU options
# (e.g. `-serial tcp::5001,server,nowait` per USART) come from $QEMU_EXTRA.
set -euo pipefail
elf=$1
serial=(${QEMU_SERIAL:--serial null -serial null -serial null})
set +e
qemu-system-arm -M netduinoplus2 -nographic -monitor none "${serial[@]}" \
  -semihosting-config enable=on,target=native ${QEMU_EXTRA:-} -kernel "$elf" \
  | defmt-print -e "$elf"
rc=${PIPESTATUS[0]}
exit "$rc"
