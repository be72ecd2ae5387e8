"""README command (1)'s program: `smartfactory demo` runs the candy factory as processes on this
host (plant, smart robot IPC, gateways, order service, cloud into SQLite), makes a small stream of
generated orders and ends with a summary (with each machine's utilisation); the run directory keeps the historian with every box's
inspection. Bad options are refused with exit 2.
"""
import json
import os
import tempfile

from line_harness import CONTROLLERS
from sftest import binary, check, json_events, run

ORDERS = 2


def main():
    bad = run([binary(), "demo", "--orders", "0"], check_rc=False)
    check(bad.returncode == 2 and "--orders" in bad.stderr, f"--orders 0 is refused with exit 2: {bad.stderr.strip()}")
    with tempfile.TemporaryDirectory(prefix="demo_test_") as tmp:
        run_dir = os.path.join(tmp, "run")
        proc = run([binary(), "demo", "--orders", str(ORDERS), "--seed", "5", "--run-dir", run_dir, "--json"],
                   timeout=420, check_rc=False)
        summary = json_events(proc.stdout, "summary")
        check(proc.returncode == 0 and len(summary) == 1, f"the demo ends with exit 0 and one summary (exit "
              f"{proc.returncode}):\n{proc.stdout[-2000:]}\n{proc.stderr[-3000:]}")
        s = summary[0]
        check(s["done"] == ORDERS and s["failed"] == 0 and s["lost"] == 0,
              f"every order done, none failed or lost: {s}")
        check(0 < s["lead_time_s"]["p50"] <= s["lead_time_s"]["p99"] and s["boxes_per_hour"] > 0,
              f"lead times and throughput: {s}")
        u = s["utilisation"]
        check(set(u) == set(CONTROLLERS) and all(0 <= x <= 1 for x in u.values()),
              f"a utilisation for every machine, between 0 and 1: {u}")
        # Two boxes went through: the uploader, the downloader and the belts they stand on worked.
        check(all(u[m] > 0 for m in ["uploader", "downloader", "conveyor1", "conveyor4"]),
              f"the machines every box passes had jobs in work: {u}")
        progress = json_events(proc.stdout, "progress")
        check(progress and progress[-1]["done"] == ORDERS, f"progress while it ran: {progress[-3:]}")
        samples = json.loads(run([binary(), "history", "query", "--db", f"sqlite:{run_dir}/history.db", "--series",
                                  "/Objects/OrderService/LastInspection", "--server", "orders", "--from", "-1h",
                                  "--json"]).stdout)["samples"]
        inspected = {str(x["value"]).split()[0] for x in samples if x["value"]}
        check(inspected == {f"demo-{i + 1}" for i in range(ORDERS)},
              f"the cloud's historian in the run directory holds every box's inspection: {inspected}")
        check(os.path.exists(os.path.join(run_dir, "log", "scara-robot-1.log")), "each process's log is kept")


main()
