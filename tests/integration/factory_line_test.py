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
import os
import tempfile
import uuid

from line_harness import (CONTROLLERS, check_dds_layout, check_history, check_orders_done, free_port_range, history,
                          stop_line, wait_ready, write_cloud_config, write_orders)
from sftest import Background, binary, check, wait_for

PARTITION = f"factory-it-{uuid.uuid4().hex[:8]}"
ORDERS = 20


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
            ready = {p["name"]: p for p in wait_ready(line)["processes"]}
            check("cloud" in ready and "orders" in ready, f"the line runs the cloud and the order service: {list(ready)}")
            endpoint = ready["orders"]["opcua"]
            check_dds_layout(PARTITION)
            check_orders_done(endpoint, ORDERS)
            wait_for(lambda: history(tmp, "series") is not None, 30, "the historian has series")
            check_history(tmp, [f"it-{i + 1}" for i in range(ORDERS)])
        finally:
            rc = stop_line(line, os.path.join(tmp, "run"))
        check(rc == 0, f"SIGINT stops the line with exit 0 (exit {rc})")


main()
