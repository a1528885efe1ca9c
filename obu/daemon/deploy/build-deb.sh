#!/bin/sh
# Builds the obu Debian package from an already-built release binary.
#
#   obu/daemon/deploy/build-deb.sh TARGET_TRIPLE [OUT_DIR]
#
# TARGET_TRIPLE: x86_64-unknown-linux-gnu (amd64), aarch64-unknown-linux-gnu (arm64) or
# armv7-unknown-linux-gnueabihf (armhf). The binary is taken from
# ${CARGO_TARGET_DIR:-target}/TRIPLE/release/obu (cargo build --release --target TRIPLE), or
# for the host triple from ${CARGO_TARGET_DIR:-target}/release/obu. Only the binary differs
# between architectures. Writes OUT_DIR/obu_VERSION_ARCH.deb (OUT_DIR: target/deb) and
# prints its path. Needs dpkg-deb, readelf and gzip; run from anywhere.
set -eu

die() { echo "build-deb: $*" >&2; exit 1; }

[ $# -ge 1 ] && [ $# -le 2 ] || die "usage: build-deb.sh TARGET_TRIPLE [OUT_DIR]"
triple=$1
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
target_dir=${CARGO_TARGET_DIR:-$root/target}
out_dir=${2:-$target_dir/deb}

# The Debian architecture and the binutils prefix of its strip (Debian's cross binutils).
case $triple in
    x86_64-unknown-linux-gnu) arch=amd64 strip_prefix=x86_64-linux-gnu- ;;
    aarch64-unknown-linux-gnu) arch=arm64 strip_prefix=aarch64-linux-gnu- ;;
    armv7-unknown-linux-gnueabihf | arm-unknown-linux-gnueabihf)
        arch=armhf strip_prefix=arm-linux-gnueabihf- ;;
    *) die "no Debian architecture known for $triple" ;;
esac

bin=$target_dir/$triple/release/obu
if [ ! -f "$bin" ] && [ "$triple" = "$(rustc -vV 2>/dev/null | sed -n 's/^host: //p')" ]; then
    bin=$target_dir/release/obu
fi
[ -f "$bin" ] || die "no release binary for $triple at $bin (cargo build --release -p obu-daemon --target $triple)"

# The workspace version ([workspace.package] version = "X.Y.Z").
version=$(sed -n '/^\[workspace\.package\]/,/^\[/s/^version *= *"\([^"]*\)".*/\1/p' "$root/Cargo.toml")
[ -n "$version" ] || die "no [workspace.package] version in $root/Cargo.toml"

# The binary's ELF machine must be the one the package says.
machine=$(readelf -h "$bin" | sed -n 's/^ *Machine: *//p')
case $arch:$machine in
    amd64:*X86-64* | arm64:*AArch64* | armhf:ARM) ;;
    *) die "$bin is for '$machine', not $arch" ;;
esac

# Depends: the libraries the binary links, glibc at least the newest symbol version it uses.
glibc=$(readelf --version-info -W "$bin" | grep -o 'GLIBC_[0-9][0-9.]*' | sed 's/GLIBC_//' |
    sort -u -V | tail -n 1)
[ -n "$glibc" ] || die "$bin uses no versioned glibc symbol: not a glibc binary?"
depends="libc6 (>= $glibc)"
for lib in $(readelf -d "$bin" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
    case $lib in
        libc.so.6 | libm.so.6 | libpthread.so.0 | libdl.so.2 | librt.so.1 | ld-linux*) ;;
        libgcc_s.so.1) depends="$depends, libgcc-s1" ;;
        *) die "$bin needs $lib: no package known for it" ;;
    esac
done

stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
pkg=$stage/obu
umask 022
mkdir -p "$pkg/DEBIAN" "$pkg/usr/bin" "$pkg/lib/systemd/system" "$pkg/etc/obu/trust" \
    "$pkg/usr/share/doc/obu"
install -m 0755 "$bin" "$pkg/usr/bin/obu"
# Stripped as dh_strip does: the target's strip, else llvm-strip (any architecture), else
# the host's strip for the host's own binaries.
strip=${STRIP:-}
for tool in "${strip_prefix}strip" llvm-strip; do
    [ -n "$strip" ] || ! command -v "$tool" >/dev/null 2>&1 || strip=$tool
done
if [ -z "$strip" ] && [ "$arch" = "$(dpkg --print-architecture)" ]; then strip=strip; fi
[ -n "$strip" ] || die "no strip for $triple (install binutils-${strip_prefix%-} or llvm, or set STRIP)"
"$strip" --remove-section=.comment --remove-section=.note --strip-unneeded "$pkg/usr/bin/obu"
install -m 0644 "$here/obu.service" "$pkg/lib/systemd/system/obu.service"
install -m 0644 "$here/obu.toml" "$pkg/etc/obu/obu.toml"
for script in postinst prerm postrm; do
    install -m 0755 "$here/debian/$script" "$pkg/DEBIAN/$script"
done
echo /etc/obu/obu.toml > "$pkg/DEBIAN/conffiles"

{
    echo "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/"
    echo "Upstream-Name: obu"
    echo
    echo "Files: *"
    echo "Copyright: 2026 the work-zone V2X authors"
    echo "License: Apache-2.0"
    echo " On Debian systems the license is also in /usr/share/common-licenses/Apache-2.0."
    echo " The project's LICENSE file follows."
    echo " ."
    sed -e 's/^[[:space:]]*$/./' -e 's/^/ /' "$root/LICENSE"
} > "$pkg/usr/share/doc/obu/copyright"
chmod 0644 "$pkg/usr/share/doc/obu/copyright"

# The changelog (a native package: changelog.gz): one entry for this version, dated by the
# binary.
date=$(date -R -u -d "@$(stat -c %Y "$bin")")
printf 'obu (%s) unstable; urgency=medium\n\n  * Built from the work-zone V2X workspace %s.\n\n -- Work-zone V2X team <obu@example.invalid>  %s\n' \
    "$version" "$version" "$date" | gzip -9n > "$pkg/usr/share/doc/obu/changelog.gz"
chmod 0644 "$pkg/usr/share/doc/obu/changelog.gz"

size=$(du -sk --exclude=DEBIAN "$pkg" | cut -f1)
cat > "$pkg/DEBIAN/control" <<EOF
Package: obu
Version: $version
Architecture: $arch
Maintainer: Work-zone V2X team <obu@example.invalid>
Installed-Size: $size
Depends: $depends
Section: net
Priority: optional
Homepage: https://example.invalid/workzone-v2x
Description: in-vehicle work-zone warning daemon (V2X MAP/TIM, GNSS, CAN)
 The OBU daemon receives MAP and TIM (IEEE 1609.2 signed) over UDP, GNSS fixes
 (NMEA or gpsd) and CAN vehicle speed, runs the work-zone alert core, and serves
 the driver's tablet app over HTTP with a live event stream.
 .
 Runs as the hardened systemd service obu.service (dynamic user, watchdog);
 configuration in /etc/obu/obu.toml, state (settings, pairing) in /var/lib/obu.
EOF

mkdir -p "$out_dir"
deb=$out_dir/obu_${version}_$arch.deb
dpkg-deb --root-owner-group -Zxz --build "$pkg" "$deb" >/dev/null
echo "$deb"
