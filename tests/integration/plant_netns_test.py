"""The plant through the CLI across network namespaces, as the paper's line
sits on its wires (§VII.A: separate interfaces per protocol): `smartfactory
plant` in one namespace serves SCARA Robot 1's EtherCAT segment on one veth
pair and the PLCs' Modbus TCP and its control port on another; in the other
namespace our EtherCAT master and Modbus clients (plant_driver) upload a box,
carry it along the belts, load it with the smart robot and with the DENSO's
controller, and download it. The plant's snapshot and event log, read back
through `plant snapshot|events`, must show both candies placed and the box
inspected.
"""
import json
import os
import sys
import tempfile

from sftest import Background, VethPair, binary, check, fail, run, run_json, wait_for_line

driver = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("SF_PLANT_DRIVER", "")
if not os.path.exists(driver):
    fail(f"plant_driver not found: {driver!r}")
work = tempfile.mkdtemp(prefix="sf-plant-")

with VethPair("sfp") as ecat:
    ip_a, ip_b = ecat.add_pair("i")
    run(["ip", "addr", "add", "10.77.0.1/24", "dev", ip_a], ns=ecat.ns_a)
    run(["ip", "addr", "add", "10.77.0.2/24", "dev", ip_b], ns=ecat.ns_b)
    plant = Background([binary(), "plant", "--json", "--ecat-iface", f"scara-robot-1={ecat.if_a}",
                        "--modbus-host", "10.77.0.1", "--control-host", "10.77.0.1", "--status-interval", "0"],
                       ns=ecat.ns_a, log=os.path.join(work, "plant.log"))
    try:
        line = wait_for_line(plant, '{"endpoints"', 20)
        endpoints = json.loads(line)["endpoints"]
        by_protocol = {}
        for e in endpoints:
            by_protocol.setdefault(e["protocol"], []).append(e)
        check(len(by_protocol.get("modbus-tcp", [])) == 9, "nine PLCs and robot controllers on Modbus TCP")
        check(all(e["address"].startswith("10.77.0.1:") for e in by_protocol["modbus-tcp"]),
              "the Modbus servers listen on the plant's IP interface")
        check(by_protocol["ethercat-raw"] == [{"machine": "scara-robot-1", "protocol": "ethercat-raw",
                                              "address": ecat.if_a}],
              "SCARA Robot 1's segment is on its own EtherCAT interface")
        control = by_protocol["control"][0]["address"]

        result = run_json([driver, line, ecat.if_b], ns=ecat.ns_b, timeout=240)
        check(result["box"] == 1, "the driver packed box 1")

        snapshot = run_json([binary(), "plant", "snapshot", "--control", control, "--json"], ns=ecat.ns_b)["snapshot"]
        counters = snapshot["counters"]
        check(counters["uploaded"] == 1 and counters["downloaded"] == 1, f"one box up and down: {counters}")
        check(counters["placed"] == 2 and counters["dropped"] == 0, f"two candies placed, none dropped: {counters}")
        check(snapshot["boxes"] == [], "the line is empty again")

        events = run_json([binary(), "plant", "events", "--control", control, "--json"], ns=ecat.ns_b)["events"]
        placed = [(e["where"], e.get("candy"), e.get("slot")) for e in events if e["kind"] == "candy_placed"]
        check(placed == [("scara-robot-1", "gummy", 3), ("denso", "lollipop", 7)],
              f"the smart robot placed a gummy in slot 3, the DENSO a lollipop in slot 7: {placed}")
        inspected = [e for e in events if e["kind"] == "box_inspected"]
        check(len(inspected) == 1 and "gummy=1 lollipop=1" in inspected[0]["detail"],
              f"the downloader's inspection counted both: {inspected}")

        # A fault through the CLI reaches the Modbus face in the other namespace.
        run([binary(), "plant", "faults", "--control", control, "inject", "plc-exception:conveyor1:6"], ns=ecat.ns_b)
        faults = run([binary(), "plant", "faults", "--control", control, "list"], ns=ecat.ns_b).stdout.split()
        check(faults == ["plc-exception:conveyor1:6"], f"the fault is listed: {faults}")
        run([binary(), "plant", "faults", "--control", control, "clear", "plc-exception:conveyor1"], ns=ecat.ns_b)
    finally:
        rc = plant.stop()
    check(rc == 0, f"the plant stopped cleanly on SIGTERM (exit {rc})")
