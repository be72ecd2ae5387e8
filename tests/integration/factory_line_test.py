"""The candy factory as processes (issue acceptance "multi-process mode", docs/factory.md): `smartfactory
line` on the default layout on loopback with the order service taking 20 orders from a file and the
cloud (`smartfactory cloud`, SQLite) subscribed to every controller's and the order service's OPC UA
server. Checks:
  - every order is done, none failed, none made twice (the order service's counters over OPC UA);
  - the DDS layout of every process is the paper's (Fig. 4), as the built-in topics show it to others
    (`smartfactory cnp layout`): the order service one product process for upload, load, download and
    transport; each gateway and the smart robot's IPC a machine for its operations; each conveyor's
    gateway also a conveyor;
  - the cloud's historian holds every machine's PackML state (from the moment the cloud found it:
    the cloud starts after the controllers) and every box's inspection (the order service's
    LastInspection series, one per order).
"""
import json
import os
import random
import signal
import socket
import tempfile
import uuid

from sftest import Background, binary, check, fail, json_events, run, wait_for

PARTITION = f"factory-it-{uuid.uuid4().hex[:8]}"
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


def free_port_range(count):
    """`count` consecutive TCP ports on 127.0.0.1 that are free now."""
    for _ in range(50):
        base = random.randint(20000, 60000)
        socks = []
        try:
            for port in range(base, base + count):
                s = socket.socket()
                s.bind(("127.0.0.1", port))
                socks.append(s)
            return base
        except OSError:
            continue
        finally:
            for s in socks:
                s.close()
    fail("no free range of ports")


def node_name(machine):
    return "".join(part[:1].upper() + part[1:] for part in machine.split("-"))


def write_cloud_config(tmp, base):
    """The controllers' OPC UA servers are base, base + 1, ... in start order; the order service's
    follows them. All of the line's processes share the installation's PKI folder."""
    path = os.path.join(tmp, "cloud.yaml")
    with open(path, "w") as f:
        f.write(f"historian:\n  url: sqlite:{tmp}/history.db\n  buffer: {tmp}/buffer\n  flush_ms: 50\n"
                "aggregating_server:\n  host: 127.0.0.1\n  port: 0\n  security: none\nservers:\n")
        for i, machine in enumerate(CONTROLLERS):
            f.write(f"  - name: {machine}\n    url: opc.tcp://127.0.0.1:{base + i}\n"
                    "    publishing_interval_ms: 100\n    sampling_interval_ms: 50\n"
                    f"    subscribe:\n      - browse_path: /Objects/Machines/{node_name(machine)}/PackML/Status\n"
                    "        depth: 1\n")
        f.write(f"  - name: orders\n    url: opc.tcp://127.0.0.1:{base + len(CONTROLLERS)}\n    security: none\n"
                "    publishing_interval_ms: 50\n    sampling_interval_ms: 20\n    queue_size: 100\n"
                "    subscribe:\n      - browse_path: /Objects/OrderService\n        depth: 1\n")
    return path


def counter(endpoint, name):
    proc = run([binary(), "opcua", "read", "--json", endpoint, f"nsu=urn:smartfactory:orders;s=OrderService.{name}"],
               check_rc=False)
    try:
        value = json.loads(proc.stdout)[0]
    except (json.JSONDecodeError, IndexError):
        return None
    return value.get("value") if value["status"] == "Good" else None


def topics(entities):
    return sorted(e["topic"] for e in entities)


def check_dds_layout():
    seen = json.loads(run([binary(), "cnp", "layout", "--partition", PARTITION, "--json"], timeout=60).stdout)
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


def history(tmp, *args):
    proc = run([binary(), "history", *args, "--db", f"sqlite:{tmp}/history.db", "--json"], check_rc=False)
    return json.loads(proc.stdout) if proc.returncode == 0 else None


def check_history(tmp):
    series = history(tmp, "series") or []
    print(json.dumps(series[:3], indent=1), flush=True)
    for machine in CONTROLLERS:
        path = f"/Objects/Machines/{node_name(machine)}/PackML/Status/StateCurrent"
        samples = history(tmp, "query", "--series", path, "--server", machine, "--from", "-1h") or {"samples": []}
        states = [s["value"] for s in samples["samples"]]
        # The cloud starts after the controllers reached Execute: what it holds from then on is the
        # state it found and every change since (none on a line without faults).
        check(states and states[-1] == EXECUTE, f"the historian holds {machine}'s PackML state: {states[:12]}")
    events = history(tmp, "query", "--series", "/Objects/OrderService/LastInspection", "--server", "orders",
                     "--from", "-1h") or {"samples": []}
    inspected = {str(e["value"]).split()[0] for e in events["samples"] if e["value"]}
    check(inspected == {f"it-{i + 1}" for i in range(ORDERS)},
          f"the historian holds every box's inspection ({len(inspected)} of {ORDERS})")


def main():
    with tempfile.TemporaryDirectory(prefix="factory_line_") as tmp:
        orders = os.path.join(tmp, "orders.yaml")
        write_orders(orders)
        base = free_port_range(len(CONTROLLERS) + 1)
        cloud = write_cloud_config(tmp, base)
        line = Background([binary(), "line", "--run-dir", os.path.join(tmp, "run"), "--opcua-base-port", str(base),
                           "--partition", PARTITION, "--orders", orders, "--cloud-config", cloud, "--json",
                           "--status-interval", "5"], log=os.path.join(tmp, "line.log"))
        try:
            wait_for(lambda: json_events(line.output(), "ready") or not line.alive(), 180, "every process up")
            if not line.alive():
                fail(f"the line ended before it was up:\n{line.output()}")
            ready = {p["name"]: p for p in json_events(line.output(), "ready")[0]["processes"]}
            check("cloud" in ready and "orders" in ready, f"the line runs the cloud and the order service: {list(ready)}")
            endpoint = ready["orders"]["opcua"]
            check_dds_layout()
            wait_for(lambda: (counter(endpoint, "Done") or 0) + (counter(endpoint, "Failed") or 0) >= ORDERS, 900,
                     f"{ORDERS} orders finished", interval=3)
            check(counter(endpoint, "Done") == ORDERS and counter(endpoint, "Failed") == 0,
                  f"every order done: {counter(endpoint, 'Done')} done, {counter(endpoint, 'Failed')} failed")
            check(counter(endpoint, "Remade") == 0 and counter(endpoint, "InWork") == 0,
                  "no box made twice, none left in work")
            wait_for(lambda: history(tmp, "series") is not None, 30, "the historian has series")
            check_history(tmp)
        finally:
            if line.alive():
                line.proc.send_signal(signal.SIGINT)
            try:
                rc = line.proc.wait(timeout=120)
            except Exception:  # noqa: BLE001 - reported below
                rc = None
            line.stop()
            for name in ["orders", "cloud"]:
                log = os.path.join(tmp, "run", "log", f"{name}.log")
                if os.path.exists(log):
                    print(f"--- {name}.log (tail)\n" + "".join(open(log).readlines()[-30:]), flush=True)
        check(rc == 0, f"SIGINT stops the line with exit 0 (exit {rc})")


main()
