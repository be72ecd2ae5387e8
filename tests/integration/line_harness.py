"""What the tests of the line as processes share (line, factory_line, factory_faults): the
controllers of the default layout, orders files, a cloud configuration for a line, and reading
the order service (OPC UA counters, its event lines), the plant (control port) and the historian."""
import json
import os
import random
import socket

from sftest import binary, check, fail, run

CONTROLLERS = ["scara-robot-1", "conveyor1", "conveyor2", "conveyor3", "conveyor4", "conveyor5",
               "uploader", "downloader", "toshiba", "denso"]
EXECUTE = 6  # PackMLState::Execute (OMAC PackML state numbers)
CANDY = ["chocolate", "gummy", "lollipop", "toffee"]


def node_name(machine):
    """The machine object's name in its model (line::iri_name): scara-robot-1 → ScaraRobot1."""
    return "".join(part[:1].upper() + part[1:] for part in machine.split("-"))


def write_orders(path, count, seed, prefix="it", kinds=(1, 1, 2)):
    """`count` small orders of one or two candy types, one of each (seeded), so a run takes
    minutes, not an hour. Returns the orders as (id, {candy: n})."""
    rng = random.Random(seed)
    orders = []
    with open(path, "w") as f:
        f.write("orders:\n")
        for i in range(count):
            candy = {k: 1 for k in rng.sample(CANDY, rng.choice(kinds))}
            orders.append((f"{prefix}-{i + 1}", candy))
            text = ", ".join(f"{k}: {n}" for k, n in candy.items())
            f.write(f"  - {{id: {prefix}-{i + 1}, box: small-box, candy: {{{text}}}}}\n")
    return orders


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


def write_cloud_config(tmp, base):
    """A cloud.yaml for a line whose controllers' OPC UA servers are base, base + 1, ... in start
    order and the order service's the next: every machine's PackML status and the order service,
    into SQLite at tmp/history.db. All of the line's processes share the installation's PKI folder."""
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


def order_counter(endpoint, name):
    """One of the order service's counters (OrderService.Done, ...) over OPC UA; None without answer."""
    proc = run([binary(), "opcua", "read", "--json", endpoint, f"nsu=urn:smartfactory:orders;s=OrderService.{name}"],
               check_rc=False)
    try:
        value = json.loads(proc.stdout)[0]
    except (json.JSONDecodeError, IndexError):
        return None
    return value.get("value") if value["status"] == "Good" else None


def order_events(run_dir):
    """The order service's event lines (accepted, awarded, ..., done) from its log, every run."""
    out = []
    path = os.path.join(run_dir, "log", "orders.log")
    if not os.path.exists(path):
        return out
    with open(path, errors="replace") as f:
        for line in f:
            if line.startswith('{"') and '"event":"order"' in line:
                try:
                    out.append(json.loads(line))
                except json.JSONDecodeError:
                    continue  # a line cut by a kill
    return out


def plant_control(run_dir):
    """HOST:PORT of the plant's control port, from the endpoints line in its log."""
    with open(os.path.join(run_dir, "log", "plant.log")) as f:
        line = next(l for l in f if l.startswith('{"endpoints"'))
    return next(e["address"] for e in json.loads(line)["endpoints"] if e["protocol"] == "control")


def plant_events(run_dir):
    """The plant's event log (boxes, candies, faults)."""
    return json.loads(run([binary(), "plant", "events", "--control", plant_control(run_dir), "--json"]).stdout)["events"]


def plant_snapshot(run_dir):
    return json.loads(run([binary(), "plant", "snapshot", "--control", plant_control(run_dir), "--json"]).stdout)["snapshot"]


def plant_fault(run_dir, action, fault):
    """Injects or clears a fault in the line's plant (`plant faults inject|clear FAULT`)."""
    run([binary(), "plant", "faults", "--control", plant_control(run_dir), action, fault])


def history(tmp, *args):
    """`smartfactory history ARGS` on tmp/history.db, its JSON answer (None when it fails)."""
    proc = run([binary(), "history", *args, "--db", f"sqlite:{tmp}/history.db", "--json"], check_rc=False)
    return json.loads(proc.stdout) if proc.returncode == 0 else None


def history_values(tmp, server, path):
    samples = history(tmp, "query", "--series", path, "--server", server, "--from", "-1h") or {"samples": []}
    return [s["value"] for s in samples["samples"]]


def check_inspections(tmp, order_ids):
    """The historian holds every box's inspection (the order service's LastInspection series)."""
    inspected = {str(v).split()[0] for v in history_values(tmp, "orders", "/Objects/OrderService/LastInspection") if v}
    missing = sorted(set(order_ids) - inspected)
    check(not missing, f"the historian holds every box's inspection ({len(order_ids) - len(missing)} of "
          f"{len(order_ids)}; missing {missing})")
