#!/bin/bash
# Install the package into a Debian chroot as a robot PC would take it, and check what
# it did: files and modes, the user and groups, a second install over a changed
# robot.ini (kept), a kept robot.ini of an older release (said, not changed), and a
# purge (what it installed gone, the records left). Not part of CI: it needs a release
# build (scripts/package.sh), root and debootstrap.
#
#   sudo scripts/try-package.sh [PACKAGE.deb]
#
# The chroot is made once in $CHROOT (default /var/tmp/mechweed-chroot) from the Debian
# mirror this machine's apt uses ($MIRROR to choose another).
set -euo pipefail
cd "$(dirname "$0")/.."
deb=${1:-$(ls -t target/debian/mechweed_*.deb 2>/dev/null | head -1)}
[ -f "$deb" ] || { echo "no package: run scripts/package.sh first" >&2; exit 1; }
root=${CHROOT:-/var/tmp/mechweed-chroot}
mirror=${MIRROR:-$(sed -n 's/^URIs: *//p' /etc/apt/sources.list.d/debian.sources 2>/dev/null | head -1)}
mirror=${mirror:-$(awk '/^deb /{print $2; exit}' /etc/apt/sources.list 2>/dev/null)}
step() { printf '\n== %s\n' "$*"; }
in_root() { chroot "$root" env LANG=C.UTF-8 PATH=/usr/sbin:/usr/bin:/sbin:/bin "$@"; }

if [ ! -x "$root/usr/bin/apt-get" ]; then
    step "debootstrap bookworm (minbase) into $root"
    debootstrap --variant=minbase bookworm "$root" "$mirror" >/dev/null
fi
mountpoint -q "$root/proc" || mount -t proc proc "$root/proc"
trap 'umount "$root/proc" 2>/dev/null || true' EXIT
cp "$deb" "$root/tmp/mechweed.deb"

step "install $(basename "$deb") ($(du -h "$deb" | cut -f1))"
in_root apt-get install -y -q /tmp/mechweed.deb 2>&1 | tail -3

step "what it installed"
in_root dpkg -L mechweed | grep -v '/$' | sed 's/^/  /'
in_root stat -c '  %A %U:%G %n' /usr/bin/mechweed /etc/mechweed /etc/mechweed/robot.ini \
    /etc/mechweed/keys /var/lib/mechweed /var/lib/mechweed/records
if [ -n "$(in_root find /usr/bin/mechweed -perm /6000)" ]; then
    echo "FAIL: /usr/bin/mechweed is setuid or setgid"; exit 1
fi
if command -v getcap >/dev/null && [ -n "$(getcap "$root/usr/bin/mechweed")" ]; then
    echo "FAIL: /usr/bin/mechweed has file capabilities"; exit 1
fi
echo "  /usr/bin/mechweed: no setuid, no file capabilities"
echo "  user: $(in_root id mechweed)"
echo "  conffiles:"; in_root dpkg-query -W -f='${Conffiles}\n' mechweed | sed 's/^/   /'
in_root mechweed check-config /etc/mechweed/robot.ini
in_root systemctl is-enabled mechweed.service mechweed-launcher.service 2>&1 | sed 's/^/  enabled? /' || true

step "a technician's change to robot.ini survives a second install"
in_root sed -i 's/^speed_mps = .*/speed_mps = 0.31/' /etc/mechweed/robot.ini
before=$(in_root sha256sum /etc/mechweed/robot.ini)
in_root dpkg -i /tmp/mechweed.deb 2>&1 | tail -2
after=$(in_root sha256sum /etc/mechweed/robot.ini)
[ "$before" = "$after" ] || { echo "FAIL: robot.ini changed"; exit 1; }
echo "  kept: $(in_root grep -m1 '^speed_mps' /etc/mechweed/robot.ini)"

step "a kept robot.ini of an older release: the install says what it lacks, changes nothing"
if git show c5bed0b:config/robot.ini > "$root/etc/mechweed/robot.ini" 2>/dev/null; then
    before=$(in_root sha256sum /etc/mechweed/robot.ini)
    in_root dpkg -i /tmp/mechweed.deb 2>&1 | grep -v '^(Reading\|^Preparing\|^Unpacking\|^Setting up' | sed 's/^/  /'
    after=$(in_root sha256sum /etc/mechweed/robot.ini)
    [ "$before" = "$after" ] || { echo "FAIL: the older robot.ini was changed"; exit 1; }
    echo "  unchanged; then: mechweed config upgrade"
    in_root mechweed config upgrade /etc/mechweed/robot.ini | tail -3 | sed 's/^/  /'
    in_root mechweed check-config /etc/mechweed/robot.ini
else
    echo "  (skipped: no git history here)"
fi

step "purge: what it installed goes, the records stay"
in_root sh -c 'echo t_s > /var/lib/mechweed/records/2026-12-02T10-00-00.csv'
in_root apt-get purge -y -q mechweed 2>&1 | tail -1
for gone in /usr/bin/mechweed /etc/mechweed/robot.ini /usr/lib/systemd/system/mechweed.service; do
    [ ! -e "$root$gone" ] || { echo "FAIL: $gone is still there"; exit 1; }
done
[ -f "$root/var/lib/mechweed/records/2026-12-02T10-00-00.csv" ] || { echo "FAIL: the record went"; exit 1; }
echo "  gone: /usr/bin/mechweed, /etc/mechweed ($( [ -e "$root/etc/mechweed" ] && echo 'left: '"$(ls -A "$root/etc/mechweed")" || echo removed)); kept: $(ls "$root/var/lib/mechweed/records")"
echo; echo "ok: the package installs, keeps the technician's settings, and purges cleanly"
