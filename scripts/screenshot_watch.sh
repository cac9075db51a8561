#!/usr/bin/env bash
# Makes docs/watch.png for the README: `mechweed watch` in a virtual X display (Xvfb),
# watching a headless run of the simulated robot in autonomous over the bus on this
# computer. Needs: apt-get install -y xvfb imagemagick. Not needed by CI.
set -euo pipefail
cd "$(dirname "$0")/.."

for tool in Xvfb import; do
    command -v "$tool" >/dev/null 2>&1 || {
        echo "$tool is missing: apt-get install -y xvfb imagemagick" >&2
        exit 1
    }
done
# SCREENSHOT_PROFILE=debug uses the dev profile (already built by the tests).
profile="${SCREENSHOT_PROFILE:-release}"
if [ "$profile" = debug ]; then cargo build; else cargo build --release; fi
bin="${CARGO_TARGET_DIR:-target}/$profile/mechweed"

display=":${SCREENSHOT_DISPLAY:-77}"
endpoint="tcp/127.0.0.1:${SCREENSHOT_PORT:-7467}"
Xvfb "$display" -screen 0 1280x860x24 -nolisten tcp &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null || true' EXIT
sleep 2

"$bin" run --headless --mode autonomous --duration 45 --set sim.row=scurve \
    --set "bus.listen=$endpoint" --set bus.accept_requests=operator > /dev/null &
robot=$!
DISPLAY="$display" "$bin" watch --connect "$endpoint" --duration 40 --tab plots &
watch=$!
sleep "${SCREENSHOT_AFTER_S:-30}"
DISPLAY="$display" import -window root docs/watch.png
wait "$watch" "$robot"
echo "wrote docs/watch.png"
