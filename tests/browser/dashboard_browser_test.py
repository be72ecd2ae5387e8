"""The dashboard's pages in headless Chromium against a running line (docs/dashboard.md "Pages"):
`smartfactory line` in simulation with its cloud serving the pages and the API (`--http`), users
of each role in the users file, and three scenarios driven by puppeteer-core (tests/browser/*.mjs):
  - viewer.mjs: a viewer's commands are disabled in the page, a command sent anyway is refused by
    the server and shown, the API answers 403 and the machine stays in Execute;
  - consumer.mjs: a consumer on a phone-sized screen is stopped by the order form's checks, places
    an order and follows it live until it is done, with its machines and inspection;
  - operator.mjs: an operator sees conveyor 3 turn Aborted live when the plant jams it, the
    knowledge loop's alarm with its rule and facts, acknowledges it, clears, resets, starts, holds
    and unholds the belt from the page; trends zoom, OEE and the Contract Net are shown.
Screenshots of every page go to $SF_SCREENSHOTS (build/<preset>/browser-screenshots, kept by CI).
Skipped (77) without Chromium or the npm packages (scripts/setup installs both)."""
import os
import re
import shutil
import subprocess
import tempfile
import uuid

from line_harness import CONTROLLERS, free_port_range, plant_control, stop_line, wait_ready
from sftest import Background, binary, check, fail, run, skip, source_dir, wait_for

CHROMIUM = os.environ.get("SF_CHROMIUM", "/usr/bin/chromium")
USERS = {"alice": "consumer", "victor": "viewer", "olga": "operator"}
PASSWORD = "candy-" + uuid.uuid4().hex[:12]


def prerequisites():
    """The browser, node with puppeteer-core and uPlot, and the built web root; skips without them."""
    if not os.path.exists(CHROMIUM):
        skip(f"no Chromium at {CHROMIUM} (scripts/setup installs Debian's chromium)")
    if shutil.which("node") is None:
        skip("node is not installed (scripts/setup installs it)")
    for package in ["puppeteer-core", "uplot"]:
        if not os.path.isdir(os.path.join(source_dir(), "node_modules", package)):
            skip(f"{package} is not installed (scripts/setup runs npm ci)")
    web_root = os.environ.get("SF_WEB_ROOT", "")
    for page in ["index.html", "operator.html", "vendor/uPlot.esm.js"]:
        if not os.path.exists(os.path.join(web_root, page)):
            fail(f"the web root {web_root!r} has no {page} (the build's dashboard_web target makes it)")
    return web_root


def write_users(tmp):
    """A users file with one user of each role, all with the same password."""
    path = os.path.join(tmp, "users.yaml")
    secret = os.path.join(tmp, "password")
    with open(secret, "w") as f:
        f.write(PASSWORD + "\n")
    for user, role in USERS.items():
        run([binary(), "opcua", "users", "add", path, user, "--role", role, "--password-file", secret])
    return path


def dashboard_url(line, run_dir):
    """The dashboard's URL the cloud printed in its log ("dashboard on http://HOST:PORT/")."""
    pattern = re.compile(r"dashboard on (https?://[^/\s]+)")
    found = []

    def printed():
        log = os.path.join(run_dir, "log", "cloud.log")
        if not line.alive():
            fail(f"the line ended:\n{line.output()}")
        match = pattern.search(open(log, errors="replace").read()) if os.path.exists(log) else None
        if match:
            found.append(match.group(1))
        return bool(match)

    wait_for(printed, 120, "the dashboard's URL from the cloud", interval=0.5)
    return found[0]


def scenario(script, url, user, screenshots, *args):
    """Runs tests/browser/<script> in node; fails the test when it fails."""
    cmd = ["node", os.path.join(source_dir(), "tests", "browser", script), "--url", url, "--user", user,
           "--password", PASSWORD, "--screenshots", screenshots, "--chromium", CHROMIUM, *args]
    print("$ " + " ".join(c if c != PASSWORD else "***" for c in cmd), flush=True)
    proc = subprocess.run(cmd, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=1200,
                          cwd=source_dir())
    print(proc.stdout, flush=True)
    check(proc.returncode == 0, f"{script} as {user} ({USERS[user]}) passed")


def main():
    prerequisites()
    screenshots = os.environ.get("SF_SCREENSHOTS") or os.path.abspath("browser-screenshots")
    os.makedirs(screenshots, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="dashboard_browser_") as tmp:
        users = write_users(tmp)
        run_dir = os.path.join(tmp, "run")
        base = free_port_range(len(CONTROLLERS) + 1)
        # A port of its own, not 0: a cloud the supervisor starts again listens where the pages were.
        http = free_port_range(1)
        line = Background([binary(), "line", "--run-dir", run_dir, "--opcua-base-port", str(base),
                           "--partition", f"dashboard-browser-{uuid.uuid4().hex[:8]}",
                           "--historian", f"sqlite:{tmp}/history.db", "--http", str(http),
                           "--web-users", users, "--json", "--status-interval", "2"],
                          log=os.path.join(tmp, "line.log"))
        rc = None
        try:
            wait_ready(line)
            url = dashboard_url(line, run_dir)
            print(f"note: dashboard at {url}", flush=True)
            scenario("viewer.mjs", url, "victor", screenshots, "--machine", "conveyor2")
            scenario("consumer.mjs", url, "alice", screenshots)
            scenario("operator.mjs", url, "olga", screenshots, "--sf-bin", binary(), "--plant-control",
                     plant_control(run_dir), "--machine", "conveyor3", "--fault", "jam:conveyor3")
        finally:
            rc = stop_line(line, run_dir)
        check(rc == 0, f"SIGINT stops the line with exit 0 (exit {rc})")


main()
