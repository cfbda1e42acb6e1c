#!/usr/bin/python3
# SPDX-License-Identifier: MIT
# The control page (firmware/control_page/) in a real browser against a real broker: a mosquitto
# of its own on loopback (MQTT for the players, WebSockets and the page's files for the browser;
# boards/mosquitto/acl as shipped), three headless vpe-player nodes, and Debian's headless
# Chromium driven by Debian's chromedriver through python3-selenium.
#
#   control_page_scenario.py --player P --write-bundle W --write-installation I --page DIR
#                            --acl ACL [--report] [--screenshots DIR] [--keep DIR]
#
# Checks: the page loads without console errors; three node cards show within 2 s of logging
# in; a drag on the sphere moves every player's light (their --json); a preset press reaches all
# three; blackout reaches all three; the install steps: a scan started from the page on node-a
# (a simulated camera on a small installation, the smallest [scan] settings) completes, its
# progress bar reaches 100 %, the camera's view and the coverage map show on the page, the other
# two nodes keep drawing meanwhile and node-a's show resumes; a killed player's card turns red
# within 4 s; the viewer role cannot move the light nor start a scan (its buttons disabled, its
# command refused by the broker); a wrong password is refused with the message shown. The last
# line of stdout is one JSON object; with --report the thresholds are not enforced (the exit
# status is 0 when the scenario ran). Exit 77 (ctest's SKIP) when a tool is absent.
import argparse
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

SKIP = 77
USERS = {"vpe-controller": "controller-secret", "vpe-player": "player-secret",
         "vpe-viewer": "viewer-secret"}
NODES = ["node-a", "node-b", "node-c"]


def skip(why):
    print("SKIP: " + why)
    sys.exit(SKIP)


def free_port():
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def wait_for(condition, limit, step=0.02):
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(step)
    return condition()


class Broker:
    def __init__(self, folder, acl, page):
        self.folder = folder
        os.makedirs(folder, exist_ok=True)
        self.mqtt_port, self.ws_port = free_port(), free_port()
        passwords = os.path.join(folder, "passwords")
        open(passwords, "w").close()
        for user, password in USERS.items():
            subprocess.run(["/usr/bin/mosquitto_passwd", "-b", passwords, user, password],
                           check=True)
        with open(os.path.join(folder, "mosquitto.conf"), "w") as conf:
            if os.geteuid() == 0:
                conf.write("user root\n")
            conf.write(f"listener {self.mqtt_port} 127.0.0.1\n"
                       f"listener {self.ws_port} 127.0.0.1\nprotocol websockets\n"
                       f"http_dir {page}\n"
                       f"allow_anonymous false\npassword_file {passwords}\nacl_file {acl}\n"
                       f"log_dest file {folder}/mosquitto.log\n")
        self.process = subprocess.Popen(
            ["/usr/sbin/mosquitto", "-c", os.path.join(folder, "mosquitto.conf")],
            stdout=open(os.path.join(folder, "mosquitto.out"), "w"), stderr=subprocess.STDOUT)

        def accepts():
            for port in (self.mqtt_port, self.ws_port):
                try:
                    socket.create_connection(("127.0.0.1", port), 0.2).close()
                except OSError:
                    return False
            return True
        if not wait_for(accepts, 5):
            raise RuntimeError("mosquitto did not start: " +
                               open(os.path.join(folder, "mosquitto.out")).read())

    def stop(self):
        self.process.terminate()
        self.process.wait(5)


class Node:
    def __init__(self, name, folder, player, bundle, port, scene):
        self.name, self.folder, self.player, self.bundle = name, folder, player, bundle
        self.runs, self.process = 0, None
        self.board = os.path.join(folder, name + ".toml")
        self.scan_out = os.path.join(folder, name + "-scan")
        with open(self.board, "w") as board:
            board.write(
                "[display]\nbackend = \"headless\"\n[render]\nrate = 30\n"
                "[light]\nazimuth = [-90, 90]\nelevation = [0, 80]\ndistance = [0.05, 5]\n"
                "initial_distance = 0.6\nsmoothing_s = 0.12\n"
                "[idle]\nenabled = true\nquiet_s = 1.5\nperiod_s = 6\nhandover_s = 0.5\n"
                "[osc]\nenabled = false\n"
                f"[bus]\nhost = \"127.0.0.1\"\nport = {port}\nusername = \"vpe-player\"\n"
                f"password = \"{USERS['vpe-player']}\"\nshow = \"gallery\"\nrole = \"player\"\n"
                f"client_id = \"{name}\"\n"
                # The smallest sequence the simulated installation allows: 26 patterns.
                f"[scan]\nsimulate = \"{scene}\"\nlatency_ms = 0\nphase_period = 64\n"
                f"phase_steps = 3\nradiometry = false\nout = \"{self.scan_out}\"\n")

    def path(self, suffix):
        return os.path.join(self.folder, f"{self.name}-{self.runs}.{suffix}")

    def start(self):
        self.runs += 1
        self.process = subprocess.Popen(
            [self.player, "--board", self.board, "--bundle", self.bundle, "--json"],
            stdout=open(self.path("out"), "w"), stderr=open(self.path("err"), "w"))

    def stop(self, how=signal.SIGTERM):
        self.process.send_signal(how)
        self.process.wait(10)
        if how != signal.SIGTERM:
            return None
        text = open(self.path("out")).read()
        return json.loads(text[text.rfind("\n{") + 1:])

    def connected(self):
        return "bus: connected to" in open(self.path("err")).read()

    def log(self):
        return open(self.path("err")).read()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--player", required=True)
    parser.add_argument("--write-bundle", required=True)
    parser.add_argument("--write-installation", required=True)
    parser.add_argument("--page", required=True)
    parser.add_argument("--acl", required=True)
    parser.add_argument("--report", action="store_true")
    parser.add_argument("--screenshots")
    parser.add_argument("--keep")
    args = parser.parse_args()

    for tool in ("/usr/sbin/mosquitto", "/usr/bin/mosquitto_passwd", "/usr/bin/chromium",
                 "/usr/bin/chromedriver"):
        if not os.access(tool, os.X_OK):
            skip(tool + " is absent (scripts/install-deps.sh --test: mosquitto, chromium, "
                 "chromium-driver)")
    try:
        from selenium import webdriver
        from selenium.webdriver.common.action_chains import ActionChains
        from selenium.webdriver.chrome.service import Service
        from selenium.webdriver.common.by import By
    except ImportError:
        skip("python3-selenium is absent (scripts/install-deps.sh --test)")
    if not os.path.exists(os.path.join(args.page, "mqtt.min.js")):
        sys.exit(f"{args.page}: no staged page (build the vpe_control_page target)")

    folder = args.keep or tempfile.mkdtemp(prefix="vpe-control-page-")
    os.makedirs(folder, exist_ok=True)
    bundle = os.path.join(folder, "scene.vpeb")
    subprocess.run([args.write_bundle, "--out", bundle, "--size", "160x90"], check=True,
                   stdout=subprocess.DEVNULL)
    scene = subprocess.run([args.write_installation, os.path.join(folder, "installation")],
                           check=True, capture_output=True, text=True).stdout.strip()
    broker = Broker(os.path.join(folder, "broker"), os.path.abspath(args.acl),
                    os.path.abspath(args.page))
    nodes = [Node(name, folder, args.player, bundle, broker.mqtt_port, scene) for name in NODES]
    for node in nodes:
        node.start()
    driver = None
    result = {}
    problems = []
    try:
        if not wait_for(lambda: all(node.connected() for node in nodes), 15):
            raise RuntimeError("the players did not connect: " +
                               " | ".join(open(n.path("err")).read() for n in nodes))
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        for flag in ("--headless=new", "--no-sandbox", "--disable-gpu",
                     "--disable-dev-shm-usage", "--window-size=1280,900"):
            options.add_argument(flag)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"),
                                  options=options)
        console = []

        def collect_console():
            console.extend(entry for entry in driver.get_log("browser")
                           if entry["level"] == "SEVERE")

        url = f"http://127.0.0.1:{broker.ws_port}/"

        def login(user, password):
            driver.get(url)
            collect_console()
            driver.find_element(By.ID, "user").clear()
            driver.find_element(By.ID, "user").send_keys(user)
            driver.find_element(By.ID, "password").send_keys(password)
            started = time.monotonic()
            driver.find_element(By.CSS_SELECTOR, "#login button[type=submit]").click()
            return started

        def cards():
            return driver.find_elements(By.CSS_SELECTOR, "#cards .card")

        def fresh_cards():
            return [c for c in cards() if c.get_attribute("data-stale") == "false"]

        def drag(dx, dy):
            canvas = driver.find_element(By.ID, "sphere")
            actions = ActionChains(driver, duration=20)
            actions.move_to_element_with_offset(canvas, 0, 0).click_and_hold()
            for k in range(1, 11):
                actions.move_to_element_with_offset(canvas, dx * k // 10, dy * k // 10)
            actions.release().perform()
            return (float(canvas.get_attribute("data-azimuth")),
                    float(canvas.get_attribute("data-elevation")))

        # 1. The controller logs in: three cards.
        started = login("vpe-controller", USERS["vpe-controller"])
        wait_for(lambda: len(fresh_cards()) == 3, 10)
        result["cards_seconds"] = round(time.monotonic() - started, 2)
        if len(fresh_cards()) != 3:
            problems.append(f"{len(cards())} cards, not 3")

        # 2. A drag, then a preset, then blackout on and off.
        target = drag(-70, 40)
        time.sleep(0.3)
        target = drag(40, 30)
        time.sleep(0.5)
        driver.find_element(By.CSS_SELECTOR, "#presets button[data-preset=radial]").click()
        time.sleep(0.3)

        def statuses_say(text):
            return all(text in c.text for c in cards())
        driver.find_element(By.ID, "blackout").click()
        blackout_reached = wait_for(lambda: statuses_say("(blackout)"), 3)
        driver.find_element(By.ID, "blackout").click()
        blackout_cleared = wait_for(lambda: not any("(blackout)" in c.text for c in cards()), 3)
        result["blackout_reached"] = bool(blackout_reached and blackout_cleared)
        time.sleep(0.5)
        reports = [node.stop() for node in nodes]
        agreement = all(abs(r["light"]["azimuth"] - target[0]) < 0.1 and
                        abs(r["light"]["elevation"] - target[1]) < 0.1 for r in reports)
        result["light_target"] = [round(target[0], 2), round(target[1], 2)]
        result["light_agreement"] = agreement
        result["preset_reached"] = all(r["preset"] == "radial" for r in reports)
        if not agreement:
            problems.append("the players' lights " +
                            str([[r["light"]["azimuth"], r["light"]["elevation"]] for r in reports])
                            + f" differ from the drag's target {target}")

        # 3. The players come back (the retained state), one is killed: its card turns red.
        for node in nodes:
            node.start()
        wait_for(lambda: all(node.connected() for node in nodes), 15)
        wait_for(lambda: len(fresh_cards()) == 3, 5)
        time.sleep(1.2)

        # 3b. The install steps: a scan on node-a from the page, the others playing on.
        def statuses():
            return driver.execute_script(
                "return [...state.nodes.entries()].map(([n, v]) => "
                "[n, v.status.fps, v.status.skipped, v.status.time_us]);")

        def install(what):
            return driver.find_element(
                By.CSS_SELECTOR, f'#installs .install[data-node="node-a"] {what}')
        wait_for(lambda: install("button[data-action=scan]").is_enabled(), 5)
        # The idle drift on, so that every node has something new to draw each frame.
        driver.find_element(By.ID, "drift").click()
        time.sleep(1.0)
        begin_us = time.time() * 1e6
        started = time.monotonic()
        install("button[data-action=scan]").click()
        seen = {}  # node -> {time_us: (fps, skipped)} of the statuses made during the scan
        stale_during = set()

        def scan_finished():
            for name, fps, skipped, time_us in statuses():
                if time_us >= begin_us:
                    seen.setdefault(name, {})[time_us] = (fps, skipped)
            stale_during.update(c.get_attribute("data-node") for c in cards()
                                if c.get_attribute("data-stale") == "true")
            return driver.find_element(
                By.CSS_SELECTOR, '#installs .install[data-node="node-a"]').get_attribute(
                    "data-state") in ("done", "failed")
        finished = wait_for(scan_finished, 90, 0.1)
        done_us = time.time() * 1e6
        result["scan_seconds"] = round(time.monotonic() - started, 2) if finished else None
        # The statuses made up to a second after it too: a scan this small takes about one.
        wait_for(lambda: scan_finished() and all(
            any(t > done_us for t in seen.get(name, {})) for name in ("node-b", "node-c")),
            2.5, 0.1)
        state_text = install(".install-state").text
        result["scan_state"] = state_text
        bar = install("progress")
        result["scan_progress"] = round(float(bar.get_attribute("value")) /
                                        float(bar.get_attribute("max")), 3)
        result["scan_frames"] = int(float(bar.get_attribute("max")))

        def images_loaded():
            return [install(f"canvas.{kind}").get_attribute("data-loaded")
                    for kind in ("camera", "coverage")]
        wait_for(lambda: all(images_loaded()), 5)
        result["scan_image_sizes"] = images_loaded()
        result["scan_images"] = all(images_loaded())
        # The others drew all along: every status they made during the scan says ~30 ticks a
        # second (drawn + skipped), with frames drawn (the idle drift moves their light).
        others = {name: sorted(seen.get(name, {}).items()) for name in ("node-b", "node-c")}
        result["others_during_scan"] = {
            name: [[fps, skipped] for time_us, (fps, skipped) in rows] for name, rows in others.items()}
        result["others_kept_drawing"] = all(
            rows and all(fps + skipped >= 20 and fps > 0 for _, (fps, skipped) in rows)
            for rows in others.values()) and not (stale_during & {"node-b", "node-c"})

        # node-a's show resumes: a status made after the scan with frames drawn again.
        def resumed():
            for name, fps, skipped, time_us in statuses():
                if name == "node-a" and time_us > done_us and fps > 0 and fps + skipped >= 20:
                    return True
            return False
        result["show_resumed"] = bool(wait_for(resumed, 4, 0.1))
        # The drift off again: every node glides back to the drag's target.
        driver.find_element(By.ID, "drift").click()
        manifest = os.path.join(nodes[0].scan_out, "scan.json")
        result["scan_folder_images"] = len(json.load(open(manifest))["images"]) \
            if os.path.exists(manifest) else 0
        if args.screenshots:
            os.makedirs(args.screenshots, exist_ok=True)
            driver.set_window_size(360, 1400)
            time.sleep(0.4)
            section = driver.find_element(By.ID, "install")
            driver.execute_script("arguments[0].scrollIntoView();", section)
            section.screenshot(os.path.join(args.screenshots, "install-360.png"))
            driver.set_window_size(1280, 900)
        nodes[2].stop(signal.SIGKILL)
        killed = time.monotonic()
        red = wait_for(lambda: [c for c in cards()
                                if c.get_attribute("data-node") == "node-c" and
                                c.get_attribute("data-stale") == "true"], 10)
        result["stale_seconds"] = round(time.monotonic() - killed, 2) if red else None
        if args.screenshots:
            os.makedirs(args.screenshots, exist_ok=True)
            driver.set_window_size(1280, 900)
            driver.execute_script("window.scrollTo(0, 0);")
            time.sleep(0.4)
            driver.save_screenshot(os.path.join(args.screenshots, "laptop-1280.png"))
            driver.set_window_size(360, 1400)
            driver.execute_script("window.scrollTo(0, 0);")
            time.sleep(0.4)
            driver.save_screenshot(os.path.join(args.screenshots, "phone-360.png"))
            driver.set_window_size(1280, 900)
        collect_console()

        # 4. The viewer watches, and cannot move the light.
        login("vpe-viewer", USERS["vpe-viewer"])
        wait_for(lambda: len(cards()) == 3, 5)
        drag(-60, -50)
        refused = wait_for(lambda: "refused" in driver.find_element(By.ID, "control-error").text,
                           3)
        time.sleep(0.6)
        after = [node.stop() for node in nodes[:2]]
        result["frame_errors"] = sum(r["errors"] for r in after)
        unmoved = all(abs(r["light"]["azimuth"] - target[0]) < 0.1 and
                      abs(r["light"]["elevation"] - target[1]) < 0.1 for r in after)
        result["viewer_refused"] = bool(refused) and unmoved
        result["viewer_message"] = driver.find_element(By.ID, "control-error").text
        # Nor start a scan: its buttons are disabled, and a command it sends anyway is refused
        # by the broker and reaches no node.
        buttons = driver.find_elements(By.CSS_SELECTOR, "#installs button")
        asked = nodes[0].log().count("scan asked by")
        driver.execute_script("arguments[0].textContent = '';",
                              driver.find_element(By.ID, "control-error"))
        driver.execute_script("sendInstall('node-a', 'scan');")
        install_refused = wait_for(
            lambda: "refused" in driver.find_element(By.ID, "control-error").text, 3)
        time.sleep(0.5)
        result["viewer_install_refused"] = bool(buttons) and \
            all(not b.is_enabled() for b in buttons) and bool(install_refused) and \
            nodes[0].log().count("scan asked by") == asked
        collect_console()

        # 5. A wrong password.
        login("vpe-controller", "not-the-password")
        message = wait_for(lambda: "Wrong user name or password" in
                           driver.find_element(By.ID, "login-error").text and
                           driver.find_element(By.ID, "login-error").text, 5)
        result["bad_password_refused"] = bool(message) and \
            not driver.find_element(By.ID, "app").is_displayed()
        result["bad_password_message"] = message or \
            driver.find_element(By.ID, "login-error").text
        collect_console()
        result["console_errors"] = len(console)
        for entry in console:
            print("console: " + entry["message"], file=sys.stderr)
    finally:
        if driver is not None:
            driver.quit()
        for node in nodes:
            if node.process and node.process.poll() is None:
                node.process.kill()
                node.process.wait()
        broker.stop()
        if not args.keep and not problems:
            shutil.rmtree(folder, ignore_errors=True)

    page_bytes = {name: os.path.getsize(os.path.join(args.page, name))
                  for name in ("index.html", "control.js", "mqtt.min.js")}
    result["page_bytes"] = page_bytes
    ordered = {key: result.get(key) for key in
               ("console_errors", "cards_seconds", "light_agreement", "stale_seconds",
                "viewer_refused", "bad_password_refused", "scan_seconds", "scan_progress",
                "scan_images", "others_kept_drawing", "show_resumed", "viewer_install_refused")}
    if not args.report:
        checks = [("console_errors", result.get("console_errors") == 0),
                  ("cards_seconds <= 2", (result.get("cards_seconds") or 99) <= 2.0),
                  ("light_agreement", result.get("light_agreement") is True),
                  ("preset_reached", result.get("preset_reached") is True),
                  ("blackout_reached", result.get("blackout_reached") is True),
                  ("stale_seconds <= 4", (result.get("stale_seconds") or 99) <= 4.0),
                  ("viewer_refused", result.get("viewer_refused") is True),
                  ("scan completed", result.get("scan_seconds") is not None and
                   "done" in (result.get("scan_state") or "")),
                  ("scan_progress == 1", result.get("scan_progress") == 1.0),
                  ("scan_images", result.get("scan_images") is True),
                  ("scan folder of 26 images", result.get("scan_folder_images") == 26),
                  ("others_kept_drawing", result.get("others_kept_drawing") is True),
                  ("show_resumed", result.get("show_resumed") is True),
                  ("frame_errors == 0", result.get("frame_errors") == 0),
                  ("viewer_install_refused", result.get("viewer_install_refused") is True),
                  ("bad_password_refused", result.get("bad_password_refused") is True)]
        for name, passed in checks:
            print(("PASS " if passed else "FAIL ") + name)
        problems += [name for name, passed in checks if not passed]
    print(json.dumps({k: v for k, v in result.items() if k not in ordered}), file=sys.stderr)
    if problems:
        print("problems: " + "; ".join(problems) + f" (files in {folder})", file=sys.stderr)
    print(json.dumps(ordered))
    return 1 if problems and not args.report else 0


if __name__ == "__main__":
    sys.exit(main())
