"""What the tests of the line as processes share (line, factory_line, factory_faults): the
controllers of the default layout, orders files, a cloud configuration for a line, and reading
the order service (OPC UA counters, its event lines), the plant (control port) and the historian."""
import json
import os
import random
import signal
import socket

from sftest import binary, check, fail, json_events, run, wait_for

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
                    f"        depth: 1\n      - browse_path: /Objects/Machines/{node_name(machine)}\n"
                    "        depth: 1\n")
        f.write(f"  - name: orders\n    url: opc.tcp://127.0.0.1:{base + len(CONTROLLERS)}\n    security: none\n"
                "    publishing_interval_ms: 50\n    sampling_interval_ms: 20\n    queue_size: 100\n"
                "    subscribe:\n      - browse_path: /Objects/OrderService\n        depth: 1\n")
        f.write("knowledge:\n  due_after_s: 900\n")
    return path


def knowledge_alarms(tmp):
    """The knowledge loop's alarms in the historian (events of the server "knowledge"), oldest first:
    dicts of time, source, message, rule, active."""
    events = history(tmp, "events", "--server", "knowledge", "--from", "-1h") or []
    if isinstance(events, dict):
        events = events.get("events", [])
    alarms = []
    for e in events:
        fields = json.loads(e.get("fields") or "{}")
        alarms.append({"time": e.get("time"), "source": e.get("source_name"), "message": e.get("message"),
                       "rule": fields.get("rule"), "active": fields.get("active")})
    return alarms


def read_value(endpoint, node, ns=None):
    """A node's value over OPC UA (`opcua read`, in the network namespace `ns` when given); None
    without a Good answer."""
    proc = run([binary(), "opcua", "read", "--json", endpoint, node], ns=ns, check_rc=False)
    try:
        value = json.loads(proc.stdout)[0]
    except (json.JSONDecodeError, IndexError):
        return None
    return value.get("value") if value["status"] == "Good" else None


def order_counter(endpoint, name, ns=None):
    """One of the order service's counters (OrderService.Done, ...) over OPC UA; None without answer."""
    return read_value(endpoint, f"nsu=urn:smartfactory:orders;s=OrderService.{name}", ns)


def machine_state(endpoint, machine, ns=None):
    """A controller's PackML StateCurrent over its own OPC UA server; None without answer."""
    return read_value(endpoint, f"nsu=urn:smartfactory:machines;s={node_name(machine)}.PackML.Status.StateCurrent", ns)


def check_orders_done(endpoint, count, ns=None, timeout=900):
    """Waits until `count` orders are finished: every one done once, none failed, remade or left
    in work. Asks every 3 s (each question starts two clients, which load the line)."""
    wait_for(lambda: (order_counter(endpoint, "Done", ns) or 0) + (order_counter(endpoint, "Failed", ns) or 0) >= count,
             timeout, f"{count} orders finished", interval=3)
    done, failed = order_counter(endpoint, "Done", ns), order_counter(endpoint, "Failed", ns)
    check(done == count and failed == 0, f"every order done: {done} done, {failed} failed")
    check(order_counter(endpoint, "Remade", ns) == 0 and order_counter(endpoint, "InWork", ns) == 0,
          "no box made twice, none left in work")


def topics(entities):
    return sorted(e["topic"] for e in entities)


def check_dds_layout(partition, ns=None, interface=None):
    """The DDS layout of every process is the paper's (Fig. 4), as the built-in topics show it to
    others (`smartfactory cnp layout`, in `ns` on `interface` when given): the order service one
    product process for upload, load, download and transport; each gateway and the smart robot's
    IPC a machine for its operations; each conveyor's gateway also a conveyor."""
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


def wait_ready(line, timeout=180):
    """The `ready` event of a `smartfactory line --json` in the background, once every process is up."""
    wait_for(lambda: json_events(line.output(), "ready") or not line.alive(), timeout, "every process up")
    if not line.alive():
        fail(f"the line ended before it was up:\n{line.output()}")
    return json_events(line.output(), "ready")[0]


def stop_line(line, run_dir, logs=("orders", "cloud")):
    """SIGINT to a running line; its exit code (None when it did not end in 2 minutes), with the
    tails of some of its processes' logs printed for whoever reads a failure."""
    if line.alive():
        line.proc.send_signal(signal.SIGINT)
    try:
        rc = line.proc.wait(timeout=120)
    except Exception:  # noqa: BLE001 - reported by the caller
        rc = None
    line.stop()
    print_log_tails(run_dir, logs)
    return rc


def print_log_tails(run_dir, names, lines=30):
    """The last text lines (not the JSON events) of some of the line's processes' logs."""
    for name in names:
        log = os.path.join(run_dir, "log", f"{name}.log")
        if os.path.exists(log):
            with open(log, errors="replace") as f:
                tail = [l for l in f.readlines() if not l.startswith('{"')][-lines:]
            print(f"--- {name}.log (tail)\n" + "".join(tail), flush=True)


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
    """HOST:PORT of the plant's control port, from the latest endpoints line in its log (a run
    directory may hold an earlier run's; on a line with --hosts, reached from a namespace on the
    field network)."""
    with open(os.path.join(run_dir, "log", "plant.log")) as f:
        line = [l for l in f if l.startswith('{"endpoints"')][-1]
    return next(e["address"] for e in json.loads(line)["endpoints"] if e["protocol"] == "control")


def plant_events(run_dir):
    """The plant's event log (boxes, candies, faults)."""
    return json.loads(run([binary(), "plant", "events", "--control", plant_control(run_dir), "--json"]).stdout)["events"]


def plant_snapshot(run_dir, ns=None):
    return json.loads(run([binary(), "plant", "snapshot", "--control", plant_control(run_dir), "--json"],
                          ns=ns).stdout)["snapshot"]


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


def inspection(text):
    """An OrderService.LastInspection value (sf/line/inspection.hpp) as a dict: order, box, type,
    ordered and counted ({candy: n}), weight_g, lead_s."""
    tokens = str(text).split()
    record = {"order": tokens[0], "ordered": {}, "counted": {}}
    for token in tokens[1:]:
        key, value = token.split("=", 1)
        if key in ("ordered", "counted"):
            record[key] = {c.split(":")[0]: int(c.split(":")[1]) for c in value.split(",") if c}
        else:
            record[key] = value
    return record


def check_inspections(tmp, order_ids, remade=()):
    """The historian holds every box's inspection (the order service's LastInspection series), and
    the last box of each order (`remade`: orders whose earlier box was rejected) holds what the
    order asks for."""
    records = [inspection(v) for v in history_values(tmp, "orders", "/Objects/OrderService/LastInspection") if v]
    last = {r["order"]: r for r in records}
    missing = sorted(set(order_ids) - set(last))
    check(not missing, f"the historian holds every box's inspection ({len(order_ids) - len(missing)} of "
          f"{len(order_ids)}; missing {missing})")
    wrong = [r for r in last.values() if r["order"] in order_ids and r["ordered"] != r["counted"]]
    check(not wrong, f"every order's last box holds what the order asks for, by the historian: {wrong}")
    twice = sorted(o for o in order_ids if sum(r["order"] == o for r in records) > 1 and o not in remade)
    check(not twice, f"no order's box was inspected twice unless it was remade: {twice}")


def check_history(tmp, order_ids, states=None):
    """The historian holds every machine's PackML state and every box's inspection. The cloud starts
    after the controllers reached Execute; it reads back their states from then on (HistoryRead)
    and every change since. `states`: each machine's state now (default: Execute, on a line
    without faults), which must be the historian's last."""
    series = history(tmp, "series") or []
    print(json.dumps(series[:3], indent=1), flush=True)
    for machine in CONTROLLERS:
        expected = EXECUTE if states is None else states[machine]
        seen = history_values(tmp, machine, f"/Objects/Machines/{node_name(machine)}/PackML/Status/StateCurrent")
        check(seen and seen[-1] == expected, f"the historian holds {machine}'s PackML state ({expected} now): {seen[:12]}")
    check_inspections(tmp, order_ids)
