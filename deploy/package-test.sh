#!/bin/sh
# Installs the package in a clean Debian 12 root and takes it through its
# life: install -> start -> /readyz -> upgrade to a newer build (data and a
# changed conffile kept) -> remove (data and user kept) -> purge (both gone).
#
#   deploy/package-test.sh [OLD.deb [NEW.deb]]
#
# Without arguments it packs build/ with cpack twice: the build as it is,
# and the same build as version <version>+pkgtest1 (what an upgrade to a
# newer build does to the files, the user, the data and the unit; the
# program is the same). Needs root, debootstrap and network access to a
# Debian mirror (THERMOCOMP_MIRROR, default http://deb.debian.org/debian).
#
# The service is started by systemd when the host runs systemd (the root
# boots in systemd-nspawn); otherwise (a container without systemd) the
# unit's ExecStart runs in the chroot as its User with NOTIFY_SOCKET on a
# socket this script owns, and the script says so. Traffic stays on
# loopback (127.0.0.1, a free port set in the conffile).
set -eu

here=$(cd "$(dirname "$0")/.." && pwd)
build=${THERMOCOMP_BUILD:-$here/build}
mirror=${THERMOCOMP_MIRROR:-http://deb.debian.org/debian}
say() { printf 'package-test: %s\n' "$*"; }
die() { say "FAIL: $*"; exit 1; }

[ "$(id -u)" = 0 ] || die "needs root (debootstrap, chroot)"
command -v debootstrap >/dev/null || die "needs debootstrap (apt-get install debootstrap)"

work=$(mktemp -d /var/tmp/thermocomp-pkgtest.XXXXXX)
root=$work/root
cleanup() {
    if mountpoint -q "$root/run/notify.sock" 2>/dev/null; then umount "$root/run/notify.sock"; fi
    for m in dev/pts dev proc sys; do
        mountpoint -q "$root/$m" 2>/dev/null && umount -l "$root/$m" || true
    done
    if [ -n "${server_pid:-}" ]; then kill "$server_pid" 2>/dev/null || true; fi
    if [ "${THERMOCOMP_KEEP_PKGTEST:-0}" = 1 ]; then say "kept $work"; else rm -rf "$work"; fi
}
trap cleanup EXIT

version=$(sed -n 's/^project(thermocomp VERSION \([0-9.]*\).*/\1/p' "$here/CMakeLists.txt")
if [ $# -ge 1 ]; then
    old=$1
    new=${2:-}
else
    say "packing $build (version $version, and $version+pkgtest1 as the newer build)"
    (cd "$build" && cpack -G DEB --config CPackConfig.cmake -B "$work/old" >/dev/null)
    (cd "$build" && cpack -G DEB --config CPackConfig.cmake -B "$work/new" \
        -D CPACK_PACKAGE_VERSION="$version+pkgtest1" >/dev/null)
    old=$(ls "$work"/old/thermocomp_*_amd64.deb)
    new=$(ls "$work"/new/thermocomp_*_amd64.deb)
fi
[ -z "$new" ] || [ "$(dpkg-deb -f "$new" Version)" != "$(dpkg-deb -f "$old" Version)" ] ||
    die "the newer build has the same version as the old one"
say "old: $old ($(dpkg-deb -f "$old" Version))"
[ -z "$new" ] || say "new: $new ($(dpkg-deb -f "$new" Version))"

say "debootstrap --variant=minbase bookworm from $mirror"
debootstrap --variant=minbase bookworm "$root" "$mirror" >"$work/debootstrap.log" 2>&1 ||
    { tail -20 "$work/debootstrap.log"; die "debootstrap failed"; }
mount -t proc proc "$root/proc"
mount --rbind /sys "$root/sys"
mount --bind /dev "$root/dev"
mount --bind /dev/pts "$root/dev/pts"
cp /etc/resolv.conf "$root/etc/resolv.conf"
in_root() { chroot "$root" "$@"; }
apt_in_root() {
    in_root env DEBIAN_FRONTEND=noninteractive apt-get -y -q \
        -o Dpkg::Options::=--force-confold "$@" >>"$work/apt.log" 2>&1 ||
        { tail -30 "$work/apt.log"; die "apt-get $*"; }
}
apt_in_root update
mkdir -p "$root/tmp/debs"
cp "$old" "$root/tmp/debs/old.deb"
[ -z "$new" ] || cp "$new" "$root/tmp/debs/new.deb"

if [ -d /run/systemd/system ] && command -v systemd-nspawn >/dev/null; then
    mode=systemd
else
    mode=chroot
    say "the host runs no systemd: the unit's ExecStart runs in the chroot as User=thermocomp"
    say "with NOTIFY_SOCKET (systemd itself does not start it here)"
fi

port=$(python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])')

# Starts the service and waits for READY=1, then /readyz.
start_service() {
    if [ "$mode" = systemd ]; then
        in_root systemctl start thermocomp
        in_root systemctl is-active thermocomp >/dev/null || die "thermocomp is not active"
    else
        notify=$work/notify.sock
        rm -f "$notify" "$work/ready"
        python3 - "$notify" "$work/ready" <<'PY' &
import os, socket, sys
s = socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM)
s.bind(sys.argv[1])
os.chmod(sys.argv[1], 0o666)  # the service runs as its own user, as under systemd
s.settimeout(120)
while True:
    data = s.recv(4096).decode()
    if "READY=1" in data.split("\n"):
        open(sys.argv[2], "w").write(data)
        break
PY
        listener=$!
        while [ ! -S "$notify" ]; do sleep 0.1; done
        # The socket lives outside the root: bind it in for the service.
        touch "$root/run/notify.sock"
        mount --bind "$notify" "$root/run/notify.sock"
        exec_start=$(sed -n 's/^ExecStart=//p' "$root/lib/systemd/system/thermocomp.service")
        (cd "$root/var/lib/thermocomp" &&
            chroot --userspec=thermocomp:thermocomp "$root" env NOTIFY_SOCKET=/run/notify.sock \
            sh -c "cd /var/lib/thermocomp && exec $exec_start" >>"$work/server.log" 2>&1) &
        server_pid=$!
        wait "$listener" || die "no READY=1 from the service"
        umount "$root/run/notify.sock"
        say "notify: $(tr '\n' ' ' <"$work/ready")"
    fi
    curl -fsS "http://127.0.0.1:$port/readyz" >/dev/null || die "/readyz does not answer"
    say "started; /readyz answers on 127.0.0.1:$port"
}
stop_service() {
    if [ "$mode" = systemd ]; then
        in_root systemctl stop thermocomp
    elif [ -n "${server_pid:-}" ]; then
        children=$(pgrep -P "$server_pid" || true)
        kill "$server_pid" $children 2>/dev/null || true
        wait "$server_pid" 2>/dev/null || true
        server_pid=
    fi
}

say "install $(basename "$old")"
apt_in_root install /tmp/debs/old.deb
in_root thermocomp --version | sed 's/^/package-test:   /'
in_root getent passwd thermocomp >/dev/null || die "no user thermocomp"
[ -d "$root/var/lib/thermocomp" ] || die "no /var/lib/thermocomp"
[ "$(in_root stat -c %U:%G:%a /etc/thermocomp/thermocomp.toml)" = root:thermocomp:640 ] ||
    die "thermocomp.toml is not root:thermocomp 0640"
sed -i "s/^listen = .*/listen = \"127.0.0.1:$port\"  # changed by package-test/" \
    "$root/etc/thermocomp/thermocomp.toml"
start_service
[ -f "$root/var/lib/thermocomp/thermocomp.db" ] || die "the service made no database"
stop_service
# Some data to keep: a simulated machine, written as the service's user.
in_root runuser -u thermocomp -- thermocomp simulate --config /etc/thermocomp/thermocomp.toml \
    --machines pkg-1 --days 1 >/dev/null
start_service
curl -fsS "http://127.0.0.1:$port/api/v1/machines/pkg-1" >/dev/null || die "machine pkg-1 missing"

if [ -n "$new" ]; then
    stop_service
    say "upgrade to $(basename "$new")"
    apt_in_root install /tmp/debs/new.deb
    [ "$(in_root dpkg-query -W -f '${Version}' thermocomp)" = "$(dpkg-deb -f "$new" Version)" ] ||
        die "the upgrade did not install the newer version"
    grep -q "changed by package-test" "$root/etc/thermocomp/thermocomp.toml" ||
        die "the upgrade replaced the changed conffile"
    start_service
    curl -fsS "http://127.0.0.1:$port/api/v1/machines/pkg-1" >/dev/null ||
        die "machine pkg-1 lost in the upgrade"
    say "upgraded; the changed conffile and machine pkg-1 kept"
fi

stop_service
say "remove"
apt_in_root remove thermocomp
[ ! -e "$root/usr/bin/thermocomp" ] || die "remove left /usr/bin/thermocomp"
[ -f "$root/var/lib/thermocomp/thermocomp.db" ] || die "remove deleted the data"
in_root getent passwd thermocomp >/dev/null || die "remove deleted the user"
[ -f "$root/etc/thermocomp/thermocomp.toml" ] || die "remove deleted the conffile"
say "removed; data, user and configuration kept"

say "purge"
in_root dpkg --purge thermocomp >>"$work/apt.log" 2>&1 || die "dpkg --purge"
[ ! -e "$root/var/lib/thermocomp" ] || die "purge left /var/lib/thermocomp"
! in_root getent passwd thermocomp >/dev/null || die "purge left the user"
! in_root getent group thermocomp >/dev/null || die "purge left the group"
[ ! -e "$root/etc/thermocomp" ] || die "purge left /etc/thermocomp"
say "purged; data, user, group and configuration gone"
say "PASS ($mode mode)"
