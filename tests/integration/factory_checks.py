"""What the tests of the candy factory as processes (`smartfactory line`, with and without --hosts)
check the same way: a file of 20 small orders, the order service's counters over OPC UA, the DDS
layout of every process (paper Fig. 4) through the built-in topics, and the cloud's historian.
Commands that must reach the line's networks take `ns`, the network namespace to run them in."""
import json
import os
import random
import signal
import time

from sftest import binary, check, fail, json_events, run, wait_for

CONTROLLERS = ["scara-robot-1", "conveyor1", "conveyor2", "conveyor3", "conveyor4", "conveyor5",
               "uploader", "downloader", "toshiba", "denso"]
ORDERS = 20
EXECUTE = 6  # PackMLState::Execute
CANDY = ["chocolate", "gummy", "lollipop", "toffee"]


def write_orders(path):
    """20 small orders of one or two candy types (seeded), so the run takes minutes, not an hour."""
    rng = random.Random(24)
    with open(path, "w") as f:
        f.write("orders:\n")
        for i in range(ORDERS):
            kinds = rng.sample(CANDY, rng.choice([1, 1, 2]))
            candy = ", ".join(f"{k}: 1" for k in kinds)
            f.write(f"  - {{id: it-{i + 1}, box: small-box, candy: {{{candy}}}}}\n")


def node_name(machine):
    return "".join(part[:1].upper() + part[1:] for part in machine.split("-"))


def counter(endpoint, name, ns=None):
    """One of the order service's counters (OrderService.<name>), None when it cannot be read."""
    proc = run([binary(), "opcua", "read", "--json", endpoint, f"nsu=urn:smartfactory:orders;s=OrderService.{name}"],
               ns=ns, check_rc=False)
    try:
        value = json.loads(proc.stdout)[0]
    except (json.JSONDecodeError, IndexError):
        return None
    return value.get("value") if value["status"] == "Good" else None


def check_orders_done(endpoint, ns=None, timeout=900):
    """Waits until every order is finished; each one done once, none failed, remade or left in work.
    Asks every 2 s: each question is a process of its own, on a machine the line keeps busy."""
    deadline = time.monotonic() + timeout
    done = failed = None
    while time.monotonic() < deadline:
        done, failed = counter(endpoint, "Done", ns), counter(endpoint, "Failed", ns)
        if (done or 0) + (failed or 0) >= ORDERS:
            break
        time.sleep(2)
    else:
        fail(f"{ORDERS} orders not finished after {timeout} s: {done} done, {failed} failed, "
             f"{counter(endpoint, 'InWork', ns)} in work")
    check(done == ORDERS and failed == 0, f"every order done: {done} done, {failed} failed")
    check(counter(endpoint, "Remade", ns) == 0 and counter(endpoint, "InWork", ns) == 0,
          "no box made twice, none left in work")


def topics(entities):
    return sorted(e["topic"] for e in entities)


def check_dds_layout(partition, ns=None, interface=None):
    """The order service is one product process for upload, load, download and transport; each
    gateway and the smart robot's IPC a machine for its operations; each conveyor's gateway also a
    conveyor (Fig. 4), as `smartfactory cnp layout` sees them through the built-in topics."""
    args = [binary(), "cnp", "layout", "--partition", partition, "--json"]
    if interface:
        args += ["--interface", interface, "--settle-ms", "4000"]
    seen = json.loads(run(args, ns=ns, timeout=60).stdout)
    by_name = {}
    for p in seen:  # one entry per participant: "role/name" in one domain
        by_name.setdefault(p["participant"], {})[p["domain"]] = (topics(p["readers"]), topics(p["writers"]))
    ops = ["download", "load", "transport", "upload"]
    product = {10: (sorted(f"{o}_BID" for o in ops), sorted([f"{o}_ANNOUNCE" for o in ops] + [f"{o}_AWARD" for o in ops])),
               11: (["INFORM"], ["REQUEST"])}
    check(by_name.get("product/order-service") == product,
          f"the order service is one product process of Fig. 4: {by_name.get('product/order-service')}")

    def machine(op):
        return (sorted([f"{op}_ANNOUNCE", f"{op}_AWARD"]), [f"{op}_BID"])

    for name, op in [("uploader", "upload"), ("downloader", "download"), ("toshiba", "load"), ("denso", "load"),
                     ("scara-robot-1", "load")]:
        check(by_name.get(f"machine/{name}") == {10: machine(op)}, f"{name} is a machine for {op}: "
              f"{by_name.get(f'machine/{name}')}")
    for belt in ["conveyor1", "conveyor2", "conveyor3", "conveyor4", "conveyor5"]:
        check(by_name.get(f"machine/{belt}") == {10: machine("transport")} and
              by_name.get(f"conveyor/{belt}") == {11: (["REQUEST"], ["INFORM"])},
              f"{belt}'s gateway is a transport contractor and a conveyor")


def history(db, *args):
    proc = run([binary(), "history", *args, "--db", db, "--json"], check_rc=False)
    return json.loads(proc.stdout) if proc.returncode == 0 else None


def machine_state(endpoint, machine, ns=None):
    """A controller's PackML StateCurrent over its own OPC UA server (None when unreadable)."""
    node = f"nsu=urn:smartfactory:machines;s={node_name(machine)}.PackML.Status.StateCurrent"
    proc = run([binary(), "opcua", "read", "--json", endpoint, node], ns=ns, check_rc=False)
    try:
        value = json.loads(proc.stdout)[0]
    except (json.JSONDecodeError, IndexError):
        return None
    return value.get("value") if value["status"] == "Good" else None


def check_history(db, states=None):
    """The historian holds every machine's PackML state (from the moment the cloud found it: the
    cloud starts after the controllers) and every box's inspection (the order service's
    LastInspection series, one per order). `states`: each machine's state now (default: Execute,
    on a line without faults), which the historian's last sample must be."""
    series = history(db, "series") or []
    print(json.dumps(series[:3], indent=1), flush=True)
    for machine in CONTROLLERS:
        expected = EXECUTE if states is None else states[machine]
        path = f"/Objects/Machines/{node_name(machine)}/PackML/Status/StateCurrent"
        samples = history(db, "query", "--series", path, "--server", machine, "--from", "-1h") or {"samples": []}
        states_seen = [s["value"] for s in samples["samples"]]
        # What it holds is the state it found and every change since.
        check(states_seen and states_seen[-1] == expected,
              f"the historian holds {machine}'s PackML state ({expected} now): {states_seen[:12]}")
    events = history(db, "query", "--series", "/Objects/OrderService/LastInspection", "--server", "orders",
                     "--from", "-1h") or {"samples": []}
    inspected = {str(e["value"]).split()[0] for e in events["samples"] if e["value"]}
    check(inspected == {f"it-{i + 1}" for i in range(ORDERS)},
          f"the historian holds every box's inspection ({len(inspected)} of {ORDERS})")


def wait_ready(line, timeout=180):
    """The `ready` event of a `smartfactory line --json` in the background, once every process is up."""
    wait_for(lambda: json_events(line.output(), "ready") or not line.alive(), timeout, "every process up")
    if not line.alive():
        fail(f"the line ended before it was up:\n{line.output()}")
    return json_events(line.output(), "ready")[0]


def stop_line(line, run_dir, logs=("orders", "cloud")):
    """SIGINT to a running line; its exit code (None when it did not end), with the tails of some
    of its processes' logs printed for a failure's reader."""
    if line.alive():
        line.proc.send_signal(signal.SIGINT)
    try:
        rc = line.proc.wait(timeout=120)
    except Exception:  # noqa: BLE001 - reported by the caller
        rc = None
    line.stop()
    for name in logs:
        log = os.path.join(run_dir, "log", f"{name}.log")
        if os.path.exists(log):
            print(f"--- {name}.log (tail)\n" + "".join(open(log).readlines()[-30:]), flush=True)
    return rc
