#!/usr/bin/env bash
# Makes this x86-64 host run the OBU's ARM Linux binaries (aarch64, armv7) as if they were
# its own: Debian's cross linkers for the builds, qemu-user (static, registered with
# binfmt_misc) for the runs. A test or `hil-sim` then starts an ARM `obu` like any program;
# the C library comes from QEMU_LD_PREFIX (/usr/aarch64-linux-gnu, /usr/arm-linux-gnueabihf).
#
# Idempotent: installs only what is missing, mounts binfmt_misc and registers the two
# interpreters only when they are not there (a registration does not survive a reboot).
# Fails loudly when an ARM program still cannot run.
set -euo pipefail

as_root=()
[[ $(id -u) -eq 0 ]] || as_root=(sudo)

need=()
command -v aarch64-linux-gnu-gcc >/dev/null || need+=(gcc-aarch64-linux-gnu libc6-dev-arm64-cross)
command -v arm-linux-gnueabihf-gcc >/dev/null || need+=(gcc-arm-linux-gnueabihf libc6-dev-armhf-cross)
command -v qemu-aarch64-static >/dev/null || need+=(qemu-user-static)
command -v update-binfmts >/dev/null || need+=(binfmt-support)
if ((${#need[@]})); then
  "${as_root[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get install -y -qq "${need[@]}"
fi
rustup target list --installed | grep -q '^aarch64-unknown-linux-gnu$' ||
  rustup target add aarch64-unknown-linux-gnu
rustup target list --installed | grep -q '^armv7-unknown-linux-gnueabihf$' ||
  rustup target add armv7-unknown-linux-gnueabihf

binfmt=/proc/sys/fs/binfmt_misc
if [[ ! -e $binfmt/status ]] && ! "${as_root[@]}" mount -t binfmt_misc binfmt_misc "$binfmt"; then
  echo "cannot mount binfmt_misc at $binfmt: the ARM programs need a host that lets root register"
  echo "interpreters (a VM or a privileged container)"
  exit 1
fi
for arch in aarch64 arm; do
  [[ -e $binfmt/qemu-$arch ]] || "${as_root[@]}" update-binfmts --enable "qemu-$arch"
  [[ $(head -n 1 "$binfmt/qemu-$arch") == enabled ]] || {
    echo "qemu-$arch is registered with binfmt_misc but disabled"
    exit 1
  }
done

# The proof: a C program built by each cross compiler runs here.
probe=$(mktemp -d)
trap 'rm -rf "$probe"' EXIT
printf '#include <stdio.h>\nint main(void){puts("ok");return 0;}\n' > "$probe/p.c"
aarch64-linux-gnu-gcc "$probe/p.c" -o "$probe/a64"
arm-linux-gnueabihf-gcc "$probe/p.c" -o "$probe/arm"
[[ $(QEMU_LD_PREFIX=/usr/aarch64-linux-gnu "$probe/a64") == ok ]]
[[ $(QEMU_LD_PREFIX=/usr/arm-linux-gnueabihf "$probe/arm") == ok ]]
echo "qemu-user: aarch64 and armv7 Linux programs run on this host"
