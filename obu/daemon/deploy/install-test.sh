#!/bin/bash
# Installs the obu package in a fresh Debian 12 (bookworm) chroot and runs it as obu.service
# would; needs root, debootstrap, curl, setpriv and network access to Debian's mirror (or a
# filled cache).
#
#   obu/daemon/deploy/install-test.sh DEB
#
# Environment:
#   OBU_DEBOOTSTRAP_CACHE  where the downloaded .debs and the finished base system are kept
#                          between runs (default: ~/.cache/obu-debootstrap)
#   DEBIAN_MIRROR          default http://deb.debian.org/debian
#   KEEP_CHROOT=1          leave the chroot in place for a look after the test
#
# systemd cannot run as PID 1 in a chroot, so the test starts the binary the way the unit
# does: the same ExecStart, a dynamic-range uid with no passwd entry (as DynamicUser= gives),
# group dialout (SupplementaryGroups=), only CAP_NET_BIND_SERVICE (bounding, inheritable,
# ambient), no new privileges, UMask=0077, the state directory owned by that uid (mode 0700)
# and the working directory in it. Then: /healthz; pairing with the PIN from the log and a
# settings write; SIGTERM and a restart that keeps the settings and the paired session; an
# HTTP port below 1024 bound through the capability alone; the conffile; dpkg -r keeps the
# state, dpkg -P removes it. The unit is checked with systemd-analyze verify.
set -euo pipefail

die() { echo "install-test: FAIL: $*" >&2; exit 1; }
step() { echo "install-test: $*"; }

[ $# -eq 1 ] || die "usage: install-test.sh DEB"
deb=$(readlink -f "$1")
[ -f "$deb" ] || die "no package $1"
[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap, chroot, mounts)"
here=$(cd "$(dirname "$0")" && pwd)
cache=${OBU_DEBOOTSTRAP_CACHE:-$HOME/.cache/obu-debootstrap}
mirror=${DEBIAN_MIRROR:-http://deb.debian.org/debian}
uid=61184 # the first uid systemd hands out to DynamicUser= services
daemon_pid=
mounts=()

root=$(mktemp -d /tmp/obu-install-test.XXXXXX)
cleanup() {
    set +e
    if [ -n "$daemon_pid" ] && kill -0 "$daemon_pid" 2>/dev/null; then
        kill -KILL "$daemon_pid"
        wait "$daemon_pid" 2>/dev/null
    fi
    local i
    for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do
        umount "${mounts[i]}" 2>/dev/null || umount -l "${mounts[i]}"
    done
    if [ "${KEEP_CHROOT:-0}" = 1 ]; then
        echo "install-test: chroot kept in $root"
    elif ! findmnt -R "$root" >/dev/null 2>&1; then
        rm -rf --one-file-system "$root"
    fi
}
trap cleanup EXIT

# The base system: from the cached tarball when there is one, else debootstrap (its .debs
# cached too) and keep the result.
base=$cache/bookworm-minbase.tar
mkdir -p "$cache/debs"
if [ -f "$base" ]; then
    step "base system from $base"
    tar -xpf "$base" -C "$root"
else
    step "debootstrap --variant=minbase bookworm (debs cached in $cache/debs)"
    debootstrap --variant=minbase --cache-dir="$cache/debs" bookworm "$root" "$mirror" \
        >"$cache/debootstrap.log" 2>&1 || { tail -n 20 "$cache/debootstrap.log"; die "debootstrap"; }
    rm -rf "$root/var/cache/apt/archives/"*.deb
    tar -cpf "$base.tmp" -C "$root" . && mv "$base.tmp" "$base"
fi

# mktemp made the root 0700 (and the tarball keeps that): the service's uid must traverse /.
chmod 0755 "$root"
for m in proc sys dev; do
    mount --bind "/$m" "$root/$m"
    mounts+=("$root/$m")
done
in_root() { chroot "$root" "$@"; }

step "dpkg -i $(basename "$deb")"
cp "$deb" "$root/tmp/obu.deb"
in_root dpkg -i /tmp/obu.deb || die "dpkg -i"
in_root test -x /usr/bin/obu || die "no /usr/bin/obu"
in_root test -f /lib/systemd/system/obu.service || die "no unit"
in_root dpkg-query -W -f='${Conffiles}\n' obu | grep -q '^ /etc/obu/obu.toml ' ||
    die "/etc/obu/obu.toml is not a conffile"
if in_root sh -c 'command -v deb-systemd-helper' >/dev/null; then
    in_root test -L /etc/systemd/system/multi-user.target.wants/obu.service ||
        die "the unit was not enabled"
    step "unit enabled (multi-user.target.wants)"
fi

step "systemd-analyze verify"
# With the host's systemd (the chroot has none, and --root=chroot lacks sysinit.target): the
# installed unit, its ExecStart pointed at the installed binary inside the chroot; every
# other line is verified as installed.
mkdir -p "$root/tmp/verify"
sed "s|^ExecStart=/usr/bin/obu |ExecStart=$root/usr/bin/obu |" \
    "$root/lib/systemd/system/obu.service" >"$root/tmp/verify/obu.service"
grep -q "^ExecStart=$root/usr/bin/obu " "$root/tmp/verify/obu.service" || die "no ExecStart=/usr/bin/obu"
verify=$(systemd-analyze verify --man=no "$root/tmp/verify/obu.service" 2>&1) ||
    die "systemd-analyze verify: $verify"
[ -z "$verify" ] || die "systemd-analyze verify complains: $verify"

# The packaged config binds loopback ports that may be taken on a CI machine: move them to
# free ones in the conffile itself (as an integrator edits it).
free_port() {
    python3 -c 'import socket,sys
s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM if sys.argv[1]=="udp" else socket.SOCK_STREAM)
s.bind(("127.0.0.1",0)); print(s.getsockname()[1])' "$1"
}
http_port=$(free_port tcp)
v2x_port=$(free_port udp)
conf=$root/etc/obu/obu.toml
grep -q '^bind = "127.0.0.1:8080"$' "$conf" || die "packaged [http] bind changed: update the test"
sed -i -e "s/^bind = \"127.0.0.1:8080\"$/bind = \"127.0.0.1:$http_port\"/" \
    -e "s/^bind = \"127.0.0.1:1516\"$/bind = \"127.0.0.1:$v2x_port\"/" "$conf"
addr=127.0.0.1:$http_port

# StateDirectory=obu (owned by the service's uid, 0700), then ExecStart as the unit runs it.
install -d -m 0700 -o "$uid" -g "$uid" "$root/var/lib/obu"
dialout=$(in_root getent group dialout | cut -d: -f3)
[ -n "$dialout" ] || die "no dialout group in the chroot"
log=$root/tmp/obu.log
start_daemon() {
    : >"$log"
    chroot "$root" /bin/sh -c "umask 0077; cd /var/lib/obu && exec setpriv \
        --reuid=$uid --regid=$uid --groups=$dialout --no-new-privs \
        --bounding-set=-all,+net_bind_service --inh-caps=-all,+net_bind_service \
        --ambient-caps=-all,+net_bind_service \
        /usr/bin/obu --config /etc/obu/obu.toml" >>"$log" 2>&1 &
    daemon_pid=$!
    local i
    for i in $(seq 100); do
        [ "$(curl -s "http://$1/healthz" 2>/dev/null)" = ok ] && return 0
        kill -0 "$daemon_pid" 2>/dev/null || { cat "$log"; die "obu exited at start"; }
        sleep 0.1
    done
    cat "$log"
    die "no /healthz on $1 within 10 s"
}
stop_daemon() {
    kill -TERM "$daemon_pid"
    local status=0
    wait "$daemon_pid" || status=$?
    daemon_pid=
    [ "$status" -eq 0 ] || { cat "$log"; die "obu exited with $status on SIGTERM"; }
}

step "start as the unit would (uid $uid, CAP_NET_BIND_SERVICE only) on $addr"
start_daemon "$addr"
pin=$(sed -n 's/^obu: pairing PIN \([^ ]*\) .*/\1/p' "$log" | head -n 1)
[ -n "$pin" ] || { cat "$log"; die "no pairing PIN in the log"; }
json() { curl -s -o /dev/stderr -w '%{http_code}' -H 'Content-Type: application/json' "$@"; }
new='{"warning_distance_m":250.0,"lead_time_s":12.0,"sound":false,"units":"mph","theme":"night"}'
code=$(json -X PUT --data "$new" "http://$addr/api/settings" 2>/dev/null)
[ "$code" = 401 ] || die "an unpaired settings write got $code, not 401"
jar=$root/tmp/cookies
code=$(json -c "$jar" -X POST --data "{\"pin\":\"$pin\"}" "http://$addr/api/pair" 2>/dev/null)
[ "$code" = 200 ] || die "pairing with the logged PIN got $code"
code=$(json -b "$jar" -X PUT --data "$new" "http://$addr/api/settings" 2>/dev/null)
[ "$code" = 200 ] || die "the paired settings write got $code"
before=$(curl -s "http://$addr/api/settings")
step "paired, settings written: $before"
for f in obu-settings.json obu-settings.pairing.json; do
    [ "$(stat -c '%u %a' "$root/var/lib/obu/$f")" = "$uid 600" ] ||
        die "/var/lib/obu/$f: $(stat -c '%u %a' "$root/var/lib/obu/$f"), not $uid 600"
done

step "SIGTERM, restart"
stop_daemon
start_daemon "$addr"
after=$(curl -s "http://$addr/api/settings")
[ "$after" = "$before" ] || die "settings after the restart: $after, before: $before"
grep -q '"warning_distance_m":250' <<<"$after" || die "not the written settings: $after"
code=$(json -b "$jar" -X PUT --data "$new" "http://$addr/api/settings" 2>/dev/null)
[ "$code" = 200 ] || die "the session from before the restart got $code"
[ "$(grep -c '^obu: pairing PIN '"$pin"' ' "$log")" = 1 ] || die "the PIN changed on restart"
stop_daemon

# A port below 1024 through the ambient capability alone (the unit's AmbientCapabilities=).
low=$(python3 -c 'import socket
for p in range(900, 1000):
    s = socket.socket()
    try:
        s.bind(("127.0.0.1", p)); print(p); break
    except OSError: pass')
step "HTTP on 127.0.0.1:$low (a port below 1024)"
sed -i "s/^bind = \"127.0.0.1:$http_port\"$/bind = \"127.0.0.1:$low\"/" "$conf"
start_daemon "127.0.0.1:$low"
stop_daemon
sed -i "s/^bind = \"127.0.0.1:$low\"$/bind = \"127.0.0.1:$http_port\"/" "$conf"

step "dpkg -r keeps the state and the configuration"
in_root dpkg -r obu >/dev/null || die "dpkg -r"
in_root test ! -e /usr/bin/obu || die "/usr/bin/obu left after dpkg -r"
in_root test -f /var/lib/obu/obu-settings.json || die "dpkg -r removed the settings"
in_root test -f /etc/obu/obu.toml || die "dpkg -r removed the conffile"

step "dpkg -i again keeps the edited conffile; dpkg -P removes state and configuration"
in_root dpkg -i /tmp/obu.deb >/dev/null || die "dpkg -i after -r"
grep -q "127.0.0.1:$http_port" "$conf" || die "reinstall replaced the edited conffile"
in_root dpkg -P obu >/dev/null || die "dpkg -P"
in_root test ! -e /var/lib/obu || die "dpkg -P left /var/lib/obu"
in_root test ! -e /etc/obu/obu.toml || die "dpkg -P left /etc/obu/obu.toml"
in_root test ! -e /etc/systemd/system/multi-user.target.wants/obu.service ||
    die "dpkg -P left the unit enabled"

step "PASS"
