"""The candy factory with every process on a host of its own (issue acceptance "multi-process mode
... with --hosts in namespaces", docs/factory.md): `smartfactory line --hosts` on the default layout,
the order service taking 20 orders from a file, the cloud (SQLite) configured for the line. Each
process runs in a network namespace with an interface per protocol (paper §VII.A, Table 1). Checks:
  - each process runs in its namespace (`ip netns identify` of the pid the line reports) with the
    interfaces and addresses the ready event lists;
  - the separation: the cloud has no route to the field network; a robot's EtherCAT interface
    carries only EtherCAT (ethertype 0x88A4); DDS (UDP) only crosses the DDS interfaces, Modbus
    only the field interfaces and OPC UA only the OPC UA interfaces (tshark in the namespaces);
  - the DDS layout of every process is the paper's (`cnp layout` on the order service's DDS
    interface); every order is done once; the historian holds every machine's PackML state and
    every box's inspection (as factory_line_test);
  - a DDS network partition between the order service and one robot for 5 s (issue acceptance
    "Faults"): once SCARA Robot 1 has a load in work (its Job.JobId over OPC UA), its namespace's
    DDS interface goes down for 5 s. The robot finishes the load meanwhile (EtherCAT and OPC UA
    are other interfaces); the order service loses its liveliness after the lease (1 s), waits the
    grace (3 s) and negotiates the load again; once the link is back, the robot's INFORM-DONE of
    the withdrawn award ends the load and the machine it went to meanwhile is cancelled
    (docs/factory.md "Faults"). Checked: the order service lost the robot and hears it again, all
    20 orders are done exactly once, none failed, remade or left in work, and by the plant's ground
    truth one box per order, none lost, every candy placed once and none dropped onto a filled
    slot (no box loaded twice);
  - SIGINT ends the line with exit 0 and leaves no namespace, bridge or veth; a start whose process
    fails removes everything too, and namespaces a killed line left are removed by the next start.
"""
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
import uuid
from collections import Counter

from line_harness import (CONTROLLERS, EXECUTE, check_dds_layout, check_history, check_orders_done, history, machine_state,
                          node_name, order_events, plant_snapshot, print_log_tails, read_value, stop_line, wait_ready,
                          write_orders)
from sftest import Background, binary, check, json_events, keep_on_failure, run, skip, wait_for

PARTITION = f"factory-hosts-{uuid.uuid4().hex[:8]}"
ORDERS = 20
ETHERCAT = "0x88a4"  # ETG.1000.4 §5.2: EtherCAT frames' EtherType
ROBOT = "scara-robot-1"  # the smart robot cut off the DDS network
CUT_S = 5  # how long its DDS link is down


def namespaces(prefix):
    return [line.split()[0] for line in run(["ip", "netns", "list"]).stdout.splitlines()
            if line.startswith(prefix + "-")]


def our_root_links():
    """Links of the root namespace named as the line names its own (it makes none there)."""
    names = {line.split(":")[1].strip().split("@")[0] for line in run(["ip", "-o", "link"]).stdout.splitlines()}
    return {n for n in names if n.split("-")[0] in ("br", "ecat", "field", "dds", "opcua") or
            n in ("ecat0", "field0", "dds0", "opcua0")}


def capture(ns, interface, seconds=6):
    """tshark on an interface of a namespace in the background, niced (the plant must keep its
    EtherCAT cycle): one line per frame with its EtherType, IP protocol and TCP/UDP ports."""
    cmd = ["ip", "netns", "exec", ns, "nice", "-n", "19", "tshark", "-i", interface, "-a", f"duration:{seconds}", "-n", "-T", "fields",
           "-e", "eth.type", "-e", "ip.proto", "-e", "tcp.port", "-e", "udp.port"]
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)


def frames(proc):
    out, _ = proc.communicate(timeout=60)
    return [line.split("\t") for line in out.splitlines() if line.strip()]


def port_of(url):
    return int(url.rsplit(":", 1)[1])


def check_namespaces(ready):
    for p in ready["processes"]:
        ns = run(["ip", "netns", "identify", str(p["pid"])]).stdout.strip()
        check(ns == p["netns"] and os.path.realpath(f"/proc/{p['pid']}/exe") == os.path.realpath(binary()),
              f"{p['name']} (pid {p['pid']}) is smartfactory itself, in {p['netns']}: {ns}")
        # "2: dds0    inet 10.77.2.3/24 brd ..."
        seen = {(f[1], f[3]) for f in (line.split() for line in
                                       run(["ip", "-n", p["netns"], "-o", "-4", "addr"]).stdout.splitlines())}
        listed = {(i["name"], f"{i['address']}/24") for i in p["interfaces"] if i["address"]}
        check(seen - {("lo", "127.0.0.1/8")} == listed, f"{p['name']}'s addresses are the listed ones: {sorted(seen)}")


def check_separation(ready, plant_modbus):
    by_name = {p["name"]: p for p in ready["processes"]}
    address = {name: {i["network"]: i["address"] for i in p["interfaces"]} for name, p in by_name.items()}
    cloud = by_name["cloud"]["netns"]
    links = run(["ip", "-n", cloud, "-o", "link"]).stdout
    check("opcua0" in links and "field0" not in links and "ecat0" not in links and "dds0" not in links,
          "the cloud has an OPC UA interface and nothing else")
    unreachable = run(["ip", "-n", cloud, "route", "get", address["plant"]["field"]], check_rc=False)
    check(unreachable.returncode != 0 and "unreachable" in unreachable.stderr,
          f"the cloud has no route to the plant's field network: {unreachable.stderr.strip()}")
    check(run(["ip", "-n", by_name["conveyor1"]["netns"], "route", "get", address["plant"]["field"]]).returncode == 0,
          "a gateway reaches the plant on the field network")

    robot, gateway = by_name["scara-robot-1"], by_name["conveyor1"]
    captures = {
        "robot ecat0": capture(robot["netns"], "ecat0"),
        "robot dds0": capture(robot["netns"], "dds0"),
        "robot opcua0": capture(robot["netns"], "opcua0"),
        "gateway field0": capture(gateway["netns"], "field0"),
        "gateway opcua0": capture(gateway["netns"], "opcua0"),
        "cloud opcua0": capture(cloud, "opcua0"),
    }
    seen = {name: frames(proc) for name, proc in captures.items()}
    for name, f in seen.items():
        print(f"{name}: {len(f)} frames, e.g. {f[:3]}", flush=True)
    ecat = seen["robot ecat0"]
    check(ecat and all(f[0] == ETHERCAT for f in ecat),
          f"the robot's EtherCAT interface carries EtherCAT only ({len(ecat)} frames, "
          f"{sorted({f[0] for f in ecat})})")

    def ip_frames(f, proto):  # ip.proto 6 TCP, 17 UDP; ARP has no ip.proto
        return [x for x in f if len(x) > 1 and x[1] == proto]

    dds = seen["robot dds0"]
    check(ip_frames(dds, "17") and not ip_frames(dds, "6"), "the DDS interface carries DDS (UDP) and no TCP")
    for name in ["robot opcua0", "gateway field0", "gateway opcua0", "cloud opcua0"]:
        check(not ip_frames(seen[name], "17"), f"no DDS (UDP) on the {name} interface")
    # OPC UA interfaces carry the process's OPC UA server (or, at the cloud, the servers it reads);
    # the field interface the gateway's PLC.
    opcua_ports = {port_of(p["opcua"]) for p in ready["processes"] if p["opcua"]}
    # A controller's OPC UA traffic may pause (nothing changed, no keep-alive due): those may be quiet.
    for name, ports, busy in [("robot opcua0", {port_of(robot["opcua"])}, False),
                              ("gateway opcua0", {port_of(gateway["opcua"])}, False),
                              ("cloud opcua0", opcua_ports, True), ("gateway field0", {plant_modbus["conveyor1"]}, True)]:
        tcp = ip_frames(seen[name], "6")
        stray = [x for x in tcp if not ports & {int(p) for p in x[2].split(",") if p}]
        check((tcp or not busy) and not stray,
              f"the {name} interface carries its protocol's TCP only ({len(tcp)} frames; stray {stray[:3]})")


def plant_modbus_ports(run_dir):
    """The PLCs' Modbus ports, from the gateways' configurations the line wrote."""
    ports = {}
    for name in ["conveyor1"]:
        with open(os.path.join(run_dir, "config", f"{name}.yaml")) as f:
            text = f.read()
        port = [line for line in text.splitlines() if "modbus" in line][0].split("port:")[1].strip(" }")
        ports[name] = int(port)
        check("host: 10.77.1.1" in text, f"{name}'s configuration names the plant's field address: {text}")
    return ports


def service_log(run_dir):
    """The order service's log (its event lines and the negotiation's log lines)."""
    with open(os.path.join(run_dir, "log", "orders.log"), errors="replace") as f:
        return f.read()


def partition_robot(by_name, run_dir):
    """Cuts SCARA Robot 1's DDS link (dds0 down in its namespace) for CUT_S seconds while it loads a
    box (its OPC UA server shows a job in work), then restores it. EtherCAT and OPC UA go on: the
    robot goes on with its job, cut off from the order service only. Returns the job's id."""
    robot, cloud = by_name[ROBOT], by_name["cloud"]["netns"]
    job_node = f"nsu=urn:smartfactory:machines;s={node_name(ROBOT)}.Job.JobId"
    jobs = []
    wait_for(lambda: jobs.append(read_value(robot["opcua"], job_node, cloud)) or jobs[-1], 600,
             f"{ROBOT} loading a box", interval=0.2)
    lost = f"contractor {ROBOT} lost liveliness"
    lost_before = service_log(run_dir).count(lost)
    run(["ip", "-n", robot["netns"], "link", "set", "dds0", "down"])
    events_before = len(order_events(run_dir))
    try:
        time.sleep(CUT_S)  # the fault's length, not a criterion
    finally:
        run(["ip", "-n", robot["netns"], "link", "set", "dds0", "up"])
    print(f"note: {ROBOT}'s DDS link was down {CUT_S} s from its job {jobs[-1]}; the order service meanwhile: "
          f"{[(e['order'], e['what'], e['machine'], e['detail']) for e in order_events(run_dir)[events_before:]]}",
          flush=True)
    check(service_log(run_dir).count(lost) > lost_before, f"the order service lost {ROBOT} while its link was down")
    wait_for(lambda: f"contractor {ROBOT} is alive again" in service_log(run_dir).split(lost)[-1], 60,
             f"the order service hears {ROBOT} again")
    return jobs[-1]


def check_made_once(run_dir, orders, plant_ns):
    """Every order done exactly once (its events), and by the plant's ground truth: one box per order,
    none lost, every candy ordered placed and none dropped onto a filled slot (no box loaded twice)."""
    done = Counter(e["order"] for e in order_events(run_dir) if e["what"] == "done")
    check(set(done) == {o for o, _ in orders} and set(done.values()) == {1}, f"every order done exactly once: {done}")
    counters = plant_snapshot(run_dir, ns=plant_ns)["counters"]
    candies = sum(sum(c.values()) for _, c in orders)
    check(counters["uploaded"] == len(orders) and counters["boxes_lost"] == 0 and counters["placed"] == candies and
          counters["dropped"] == 0, f"one box per order, {candies} candies placed, none twice: {counters}")


def check_leftovers_removed(tmp, run_dir):
    """A line killed after making its namespaces leaves them; the next start in the same run
    directory removes them first. Returns the prefix."""
    first = Background([binary(), "line", "--hosts", "--run-dir", run_dir, "--partition", PARTITION, "--json"],
                       log=os.path.join(tmp, "killed.log"))
    made = []
    try:
        wait_for(lambda: made.extend(re.findall(r"^line: (\d+) network namespaces (\S+)-\*$", first.output(),
                                                re.M)) or made, 120, "the namespaces made")
        first.proc.send_signal(signal.SIGKILL)
        first.proc.wait()
    finally:
        first.stop()  # SIGTERM: the line removes its namespaces, should the test fail before the kill
    count, prefix = int(made[0][0]), made[0][1]
    left = namespaces(prefix)
    check(len(left) == count == 13, f"a killed line leaves its namespaces (12 processes and the line's): {left}")
    return prefix


def check_failed_start(tmp, run_dir, prefix):
    """A process that does not come up ends the start with exit 1, and nothing is left."""
    bad = os.path.join(tmp, "bad-cloud.yaml")
    with open(bad, "w") as f:
        f.write("historian: [not, a, map]\n")
    proc = run([binary(), "line", "--hosts", "--run-dir", run_dir, "--partition", PARTITION,
                "--cloud-config", bad, "--json"], timeout=300, check_rc=False)
    check("removed namespaces an earlier run left" in proc.stderr,
          f"the start removed what the killed line left: {proc.stderr[:400]}")
    check(proc.returncode == 1 and "cloud" in proc.stderr, f"a cloud that does not come up fails the start "
          f"(exit {proc.returncode}): {proc.stderr[-600:]}")
    check(namespaces(prefix) == [], f"a failed start leaves no namespace: {namespaces(prefix)}")


def main():
    if os.geteuid() != 0:
        skip("needs root for network namespaces")
    for tool in ["ip", "tshark"]:
        if shutil.which(tool) is None:
            skip(f"{tool} is not installed")
    links_before = our_root_links()
    with tempfile.TemporaryDirectory(prefix="factory_hosts_") as tmp:
        run_dir = os.path.join(tmp, "run")
        prefix = check_leftovers_removed(tmp, run_dir)
        check_failed_start(tmp, run_dir, prefix)

        orders = os.path.join(tmp, "orders.yaml")
        made = write_orders(orders, ORDERS, seed=24)
        ids = [order_id for order_id, _ in made]
        db = f"sqlite:{tmp}/history.db"
        line = Background([binary(), "line", "--hosts", "--run-dir", run_dir, "--partition", PARTITION,
                           "--orders", orders, "--historian", db, "--json", "--status-interval", "5"],
                          log=os.path.join(tmp, "line.log"))
        passed = False
        try:
            ready = wait_ready(line, 240)
            check(ready["hosts"]["netns"] == f"{prefix}-net" and
                  [n["subnet"] for n in ready["hosts"]["networks"]] == ["10.77.1.0/24", "10.77.2.0/24", "10.77.3.0/24"],
                  f"the field, DDS and OPC UA networks: {ready['hosts']}")
            by_name = {p["name"]: p for p in ready["processes"]}
            check(len(namespaces(prefix)) == len(by_name) + 1, "a namespace per process and the line's own")
            check_namespaces(ready)
            check_dds_layout(PARTITION, ns=by_name["orders"]["netns"], interface="dds0")
            endpoint = by_name["orders"]["opcua"]
            check(endpoint.startswith("opc.tcp://10.77.3."), f"the order service serves on its OPC UA address: {endpoint}")
            job = partition_robot(by_name, run_dir)
            check_orders_done(endpoint, ORDERS, ns=by_name["cloud"]["netns"])
            check_made_once(run_dir, made, by_name["conveyor1"]["netns"])
            print(f"note: the cut-off job {job}: " + "; ".join(
                f"{e['what']} {e['machine']} {e['detail']}" for e in order_events(run_dir)
                if e["order"] == job.split(".")[0]), flush=True)
            wait_for(lambda: history(tmp, "series") is not None, 30, "the historian has series")
            # Every machine in Execute (no faults on this line), as its own server tells the cloud's
            # namespace, and as the historian holds it.
            states = {name: machine_state(by_name[name]["opcua"], name, by_name["cloud"]["netns"])
                      for name in CONTROLLERS}
            stopped = [name for name, state in states.items() if state != EXECUTE]
            if stopped:
                print_log_tails(run_dir, stopped, lines=20)  # why: its stop reason, its link
            check(not stopped, f"every machine in Execute: {states}")
            check_history(tmp, ids)
            # Last, so the captures' load cannot disturb the production the checks above count;
            # every protocol still talks (EtherCAT cycles, Modbus polls, DDS discovery, OPC UA).
            check_separation(ready, plant_modbus_ports(run_dir))
            passed = True
        finally:
            rc = stop_line(line, run_dir)
            if not passed:
                keep_on_failure("factory_line_hosts", tmp)
        check(rc == 0, f"SIGINT stops the line with exit 0 (exit {rc})")
        check(namespaces(prefix) == [], f"no namespace left: {namespaces(prefix)}")
        new_links = our_root_links() - links_before
        check(not new_links, f"no bridge or veth left in the root namespace: {new_links}")
        stopped = json_events(line.output(), "stopped")
        check(stopped and all(p["state"] == "stopped" for p in stopped[-1]["processes"]), "every process stopped")


main()
