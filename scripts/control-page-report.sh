#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The show's control page (docs/control-page.md) in a real browser against a real
# broker, measured on this machine: Debian's headless Chromium driven by chromedriver
# (python3-selenium), a mosquitto of the script's own on loopback (MQTT for the players,
# WebSockets and the page's files for the browser, boards/mosquitto/acl as shipped), three
# headless vpe-player nodes, one of which scans a small simulated installation from the page
# (the install steps). The scenario is the ctest's (tests/firmware/control_page/), with
# screenshots at phone (360 px) and laptop (1280 px) widths, and of the install section at
# 360 px after the scan, saved into docs/control-page/.
#   scripts/control-page-report.sh [--screenshots DIR]
# The last line of stdout is one JSON object:
#   console_errors        SEVERE entries of the browser's console over the whole scenario
#   cards_seconds         from pressing "Log in" to three node cards showing, all fresh
#   light_agreement       true when every player's light (its --json on SIGTERM) is within 0.1°
#                         of where the page's sphere was dragged
#   stale_seconds         from SIGKILL of one player to its card turning red
#   viewer_refused        true when the viewer's drag was refused (the message shown) and no
#                         player's light moved
#   bad_password_refused  true when a wrong password showed "Wrong user name or password" and
#                         the page stayed at its login
#   scan_seconds          from pressing "Scan" on node-a's install block to its progress saying
#                         done (26 patterns of a simulated 320 x 180 projector, 320 x 240 camera)
#   scan_progress         the progress bar's value / max when it said done (1.0: 100 %)
#   scan_images           true when the camera's view and the coverage map were drawn on the page
#   others_kept_drawing   true when every status node-b and node-c made during the scan (and up to
#                         a second after) says frames drawn, ~30 ticks a second, their cards fresh
#   show_resumed          true when node-a's status after the scan says frames drawn again
#   viewer_install_refused true when the viewer's install buttons were disabled and a command it
#                         sent anyway was refused by the broker and reached no node
set -euo pipefail
cd "$(dirname "$0")/.."
screenshots=docs/control-page
while (($#)); do
    case $1 in
        --screenshots) screenshots=$2; shift 2 ;;
        *) echo "control-page-report: unknown argument '$1'" >&2; exit 2 ;;
    esac
done
scripts/install-deps.sh --test
cmake --preset release >/dev/null
cmake --build --preset release --target vpe-player vpe_write_test_bundle vpe_control_page \
    vpe_write_scan_installation -j "$(nproc)" >&2
/usr/bin/python3 tests/firmware/control_page/control_page_scenario.py --report \
    --player build/release/firmware/player/vpe-player \
    --write-bundle build/release/tests/firmware/bus/vpe_write_test_bundle \
    --write-installation build/release/tests/firmware/control_page/vpe_write_scan_installation \
    --page build/release/firmware/control_page/www \
    --acl boards/mosquitto/acl \
    --screenshots "$screenshots"
