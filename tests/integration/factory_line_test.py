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
import signal
import tempfile
import uuid

from line_harness import (CONTROLLERS, EXECUTE, check_inspections, free_port_range, history, history_values,
                          node_name, order_counter, write_cloud_config, write_orders)
from sftest import Background, binary, check, fail, json_events, run, wait_for

PARTITION = f"factory-it-{uuid.uuid4().hex[:8]}"
ORDERS = 20


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


def check_history(tmp):
    series = history(tmp, "series") or []
    print(json.dumps(series[:3], indent=1), flush=True)
    for machine in CONTROLLERS:
        states = history_values(tmp, machine, f"/Objects/Machines/{node_name(machine)}/PackML/Status/StateCurrent")
        # The cloud starts after the controllers reached Execute; it reads back their states from
        # then on (HistoryRead) and every change since (none on a line without faults).
        check(states and states[-1] == EXECUTE, f"the historian holds {machine}'s PackML state: {states[:12]}")
    check_inspections(tmp, [f"it-{i + 1}" for i in range(ORDERS)])


def main():
    with tempfile.TemporaryDirectory(prefix="factory_line_") as tmp:
        orders = os.path.join(tmp, "orders.yaml")
        write_orders(orders, ORDERS, seed=24)
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
            wait_for(lambda: (order_counter(endpoint, "Done") or 0) + (order_counter(endpoint, "Failed") or 0) >= ORDERS, 900,
                     f"{ORDERS} orders finished", interval=3)
            check(order_counter(endpoint, "Done") == ORDERS and order_counter(endpoint, "Failed") == 0,
                  f"every order done: {order_counter(endpoint, 'Done')} done, {order_counter(endpoint, 'Failed')} failed")
            check(order_counter(endpoint, "Remade") == 0 and order_counter(endpoint, "InWork") == 0,
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
