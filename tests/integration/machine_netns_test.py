"""The smart robot's IPC through the CLI across network namespaces (paper
§VII.A: the IPC has an interface per protocol): `smartfactory plant` in one
namespace serves SCARA Robot 1's EtherCAT segment on a veth pair and the PLCs
on another; in the other namespace `smartfactory machine` masters the segment
over its veth end and joins the Contract Net on loopback, where a product's
manager (machine_driver) brings a box to the robot over the PLCs and
negotiates "load 3 gummies". The robot's INFORM-DONE, the plant's event log
(three gummies in slots 0-2 by scara-robot-1) and the machine's status lines
must agree, and the machine's own OPC UA server shows the job, the PackML
state and the axes along the way. Then the EtherCAT cable is cut in the plant: the machine stops
with the lost segment as its stop reason, and once the cable is back it
resets by itself and runs again.
"""
import json
import os
import sys
import tempfile

from sftest import Background, VethPair, binary, check, fail, run, run_json, wait_for, wait_for_line

driver = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SF_MACHINE_DRIVER", "")
if not os.path.exists(driver):
    fail(f"machine_driver not found: {driver!r}")
work = tempfile.mkdtemp(prefix="sf-machine-")
partition = f"machine-netns-{os.getpid()}"


def events_of(machine, kind):
    """The machine's JSON lines of one event kind ("ready", "status"), in order."""
    out = []
    for line in machine.output().splitlines():
        if line.startswith("{"):
            try:
                event = json.loads(line)
            except json.JSONDecodeError:
                continue
            if event.get("event") == kind:
                out.append(event)
    return out


def statuses(machine):
    return events_of(machine, "status")


MACHINE = "nsu=urn:smartfactory:machines;s=ScaraRobot1."


def ua_read(ns, *paths):
    """Values of the machine model's nodes over OPC UA (SignAndEncrypt, the host's PKI): {path: (status, value)}."""
    # `opcua read` exits 1 when a value is not Good; the JSON still has every value.
    proc = run([binary(), "opcua", "read", "--json", "opc.tcp://localhost:4850", *[MACHINE + p for p in paths]],
               ns=ns, check_rc=False)
    values = json.loads(proc.stdout)
    return {p: (v["status"], v.get("value")) for p, v in zip(paths, values)}


def wait_for_state(machine, state, timeout, after=0):
    wait_for(lambda: any(s["state"] == state for s in statuses(machine)[after:]), timeout,
             f"the machine in {state}")
    return len(statuses(machine))


with VethPair("sfm") as ecat:
    ip_a, ip_b = ecat.add_pair("i")
    run(["ip", "addr", "add", "10.78.0.1/24", "dev", ip_a], ns=ecat.ns_a)
    run(["ip", "addr", "add", "10.78.0.2/24", "dev", ip_b], ns=ecat.ns_b)
    run(["ip", "link", "set", "lo", "up"], ns=ecat.ns_b)
    plant = Background([binary(), "plant", "--json", "--ecat-iface", f"scara-robot-1={ecat.if_a}",
                        "--modbus-host", "10.78.0.1", "--control-host", "10.78.0.1", "--status-interval", "0"],
                       ns=ecat.ns_a, log=os.path.join(work, "plant.log"))
    machine = None
    try:
        endpoints = wait_for_line(plant, '{"endpoints"', 20)
        control = [e for e in json.loads(endpoints)["endpoints"] if e["protocol"] == "control"][0]["address"]
        config = os.path.join(work, "machine.yaml")
        with open(config, "w") as f:
            f.write(f"machine: scara-robot-1\nstart: execute\nethercat: {{link: {ecat.if_b}, cycle_us: 1000}}\n"
                    f"dds: {{interface: lo, partition: {partition}}}\nopcua: {{port: 4850}}\n")
        machine = Background([binary(), "machine", "--config", config, "--json", "--status-interval", "1"],
                             ns=ecat.ns_b, log=os.path.join(work, "machine.log"))
        wait_for(lambda: events_of(machine, "ready"), 30, "the machine to be ready")
        ready = events_of(machine, "ready")[0]
        check(ready["link"] == ecat.if_b and ready["cycle_us"] == 1000, f"the machine masters its veth: {ready}")
        wait_for_state(machine, "Execute", 30)

        product = Background([driver, endpoints, partition, "3"], ns=ecat.ns_b, log=os.path.join(work, "driver.log"))
        seen_job = None
        while product.alive() and seen_job is None:
            now = ua_read(ecat.ns_b, "Job.JobId", "PackML.Status.StateCurrent", "Tags.axis1.position",
                          "Tags.io.box_in_place.0")
            if now["Job.JobId"][1]:
                seen_job = now
        product.proc.wait(timeout=240)
        check(product.stop() == 0, f"the product's driver succeeded: {product.output()[-2000:]}")
        result = json.loads([l for l in product.output().splitlines() if l.startswith('{"box"')][-1])
        check(seen_job is not None, "the machine's OPC UA server showed the job in work")
        check(seen_job["PackML.Status.StateCurrent"] == ("Good", 6), f"in Execute (6) during the job: {seen_job}")
        check(seen_job["Tags.axis1.position"][0] == "Good" and isinstance(seen_job["Tags.axis1.position"][1], float),
              f"the shoulder axis' position is served: {seen_job}")
        check(result["done"] and result["contractor"] == "scara-robot-1",
              f"SCARA Robot 1 confirmed the load and reported INFORM-DONE: {result}")
        events = run_json([binary(), "plant", "events", "--control", control, "--json"], ns=ecat.ns_b)["events"]
        placed = [(e["where"], e.get("candy"), e.get("slot")) for e in events if e["kind"] == "candy_placed"]
        check(placed == [("scara-robot-1", "gummy", s) for s in range(3)],
              f"three gummies in slots 0-2 of the box, by the smart robot: {placed}")
        dropped = run_json([binary(), "plant", "snapshot", "--control", control, "--json"],
                           ns=ecat.ns_b)["snapshot"]["counters"]["dropped"]
        check(dropped == 0, f"no candy dropped ({dropped})")
        wait_for(lambda: any(s["done"] == 1 and s["produced"] == 1 for s in statuses(machine)), 10,
                 "the machine's status to count the job")

        seen = len(statuses(machine))
        run([binary(), "plant", "faults", "--control", control, "inject", "cable-cut:scara-robot-1"], ns=ecat.ns_b)
        seen = wait_for_state(machine, "Stopped", 15, seen)
        stopped = [s for s in statuses(machine) if s["state"] == "Stopped"][-1]
        check(stopped.get("stop_reason", {}).get("id") == 202 and stopped["fault"],
              f"the lost segment is the stop reason and the fault: {stopped}")
        wait_for(lambda: ua_read(ecat.ns_b, "Tags.axis1.position")["Tags.axis1.position"][0] != "Good", 10,
                 "the axes' values to lose their quality over OPC UA")
        down = ua_read(ecat.ns_b, "PackML.Status.StateCurrent", "PackML.Admin.StopReason.ID", "Tags.axis1.position")
        check(down["PackML.Status.StateCurrent"][1] == 2 and down["PackML.Admin.StopReason.ID"][1] == 202,
              f"OPC UA shows Stopped (2) with stop reason 202: {down}")
        check(down["Tags.axis1.position"][0].startswith("Bad"), f"the axis value is Bad: {down}")
        run([binary(), "plant", "faults", "--control", control, "clear", "cable-cut:scara-robot-1"], ns=ecat.ns_b)
        wait_for_state(machine, "Execute", 30, seen)
    finally:
        rc_machine = machine.stop() if machine else 0
        rc = plant.stop()
    check(rc_machine == 0, f"the machine stopped cleanly on SIGTERM (exit {rc_machine})")
    check(rc == 0, f"the plant stopped cleanly on SIGTERM (exit {rc})")
