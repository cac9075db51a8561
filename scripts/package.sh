#!/bin/sh
# Build the Debian package of the robot PC: target/debian/mechweed_VERSION_ARCH.deb.
#
#   scripts/package.sh
#
# Needs cargo-deb (cargo install cargo-deb --locked). A release build, the man pages
# from the program's own --help, then the package from Cargo.toml's
# [package.metadata.deb].
set -eu
cd "$(dirname "$0")/.."
if ! command -v cargo-deb >/dev/null 2>&1; then
    echo "scripts/package.sh needs cargo-deb: cargo install cargo-deb --locked" >&2
    exit 1
fi
cargo build --release
rm -rf target/man
target/release/mechweed man-pages target/man
cargo deb --no-build
ls -l target/debian/*.deb
