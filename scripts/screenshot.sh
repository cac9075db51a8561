#!/usr/bin/env bash
# Makes docs/screenshot.png for the README: the operator GUI on the simulated robot,
# driving autonomously, in a virtual X display (Xvfb) drawn by Mesa's software
# renderer; with `watch`, docs/watch.png: `mechweed watch` watching a headless run over
# the bus on this computer. Needs: apt-get install -y xvfb imagemagick. Not needed by CI.
set -euo pipefail
cd "$(dirname "$0")/.."

for tool in Xvfb import; do
    command -v "$tool" >/dev/null 2>&1 || {
        echo "$tool is missing: apt-get install -y xvfb imagemagick" >&2
        exit 1
    }
done
# SCREENSHOT_PROFILE=debug uses the dev profile (optimised in this project, and
# already built by the tests) instead of a release build.
profile="${SCREENSHOT_PROFILE:-release}"
if [ "$profile" = debug ]; then cargo build; else cargo build --release; fi
bin="${CARGO_TARGET_DIR:-target}/$profile/mechweed"

display=":${SCREENSHOT_DISPLAY:-77}"
Xvfb "$display" -screen 0 1280x720x24 -nolisten tcp &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null || true' EXIT
sleep 2

if [ "${1:-}" = watch ]; then
    endpoint="tcp/127.0.0.1:${SCREENSHOT_PORT:-7467}"
    "$bin" run --headless --mode autonomous --duration 45 --set sim.row=scurve \
        --set "bus.listen=$endpoint" --set bus.accept_requests=operator > /dev/null &
    robot=$!
    DISPLAY="$display" "$bin" watch --connect "$endpoint" --duration 40 --tab plots &
    app=$!
    picture=docs/watch.png
else
    # --mode autonomous: the scripted operator powers up and asks for Autonomous, as a
    # person would click Power up, then Autonomous. --tab plots opens the Plots tab.
    DISPLAY="$display" "$bin" run --mode autonomous --tab plots --duration 45 --set sim.row=scurve &
    app=$!
    robot=$app
    picture=docs/screenshot.png
fi
sleep "${SCREENSHOT_AFTER_S:-35}"
DISPLAY="$display" import -window root "$picture"
wait "$app" "$robot"
echo "wrote $picture"
