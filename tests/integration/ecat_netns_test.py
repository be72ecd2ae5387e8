"""EtherCAT end to end through the CLI over a real wire: `ecat sim` serves an
emulated segment on one end of a veth pair in its own network namespace;
`ecat scan`, `ecat sdo` and `ecat run` drive it from the other namespace. The
slave side records every frame to a pcap file that tshark must decode
cleanly, SDO aborts (CoE service 2) with their codes and the SDO Information
service with its object names.
"""
import json
import os
import shutil
import subprocess
import tempfile
import time

from sftest import Background, VethPair, binary, check, fail, run, run_json, skip

SPEC = "smart-controller:2,digital-io:4,servo:1"
# (device name prefix, output bits, input bits) in segment order
EXPECTED = [("smart-controller", None, None)] * 2 + [("digital-io", 8, 8)] * 4 + [("servo", None, None)]

work = tempfile.mkdtemp(prefix="sf-ecat-")
pcap = os.path.join(work, "segment.pcap")
report = os.path.join(work, "sim-report.json")

with VethPair("sfe") as wire:
    sim = Background([binary(), "ecat", "sim", "--iface", wire.if_b, "--slaves", SPEC, "--pcap", pcap,
                      "--report", report], ns=wire.ns_b, log=os.path.join(work, "sim.log"))
    try:
        time.sleep(0.5)
        check(sim.alive(), "ecat sim is serving the segment")

        # ---- scan --------------------------------------------------------
        scan = run_json([binary(), "ecat", "scan", "--iface", wire.if_a, "--json"], ns=wire.ns_a, timeout=120)
        slaves = scan["slaves"]
        check(len(slaves) == len(EXPECTED), f"scan finds {len(EXPECTED)} slaves: {len(slaves)}")
        for pos, (s, (name, out_bits, in_bits)) in enumerate(zip(slaves, EXPECTED)):
            check(s["position"] == pos and s["address"] == 0x1001 + pos,
                  f"slave {pos} has position {pos} and address {0x1001 + pos:#06x}")
            check(name in s["name"].lower().replace(" ", "-") or name in s.get("device", ""),
                  f"slave {pos} is a {name}: {s['name']}")
            check(s["vendor_id"] != 0 and s["product_code"] != 0, f"slave {pos} identity read from SII")
            if out_bits is not None:
                check(s["output_bits"] == out_bits and s["input_bits"] == in_bits,
                      f"slave {pos} maps {out_bits} output and {in_bits} input bits")
        check(slaves[0]["mailbox"] == ["CoE"] and slaves[2]["mailbox"] == [],
              "the smart controller speaks CoE, digital IO has no mailbox")
        check(all(s["dc"] for s in slaves), "every slave supports distributed clocks")
        # the smart controller: 8 axes x (16+32 out, 16+32+32 in) + 32 DO / 32 DI
        check(slaves[0]["output_bits"] == 8 * 48 + 32 and slaves[0]["input_bits"] == 8 * 80 + 32,
              "smart controller PDO sizes: 8 CiA 402 axes + 32 DO / 32 DI")

        # ---- SDO tools -----------------------------------------------------
        sdo = [binary(), "ecat", "sdo"]
        listing = run_json(sdo + ["list", "--iface", wire.if_a, "--slave", "0", "--values", "--json"],
                           ns=wire.ns_a, timeout=180)
        objects = {o["index"]: o for o in listing[0]["objects"]}
        check(0x1018 in objects and objects[0x1018]["object_code"] == "RECORD"
              and objects[0x1018]["name"] == "Identity", "sdo list: 0x1018 Identity, a RECORD")
        vendor = next(e for e in objects[0x1018]["entries"] if e["subindex"] == 1)
        check(vendor["data_type"] == "UNSIGNED32" and vendor["value"].split()[0] == str(slaves[0]["vendor_id"]),
              f"sdo list: 0x1018:01 is the vendor id the SII has ({vendor})")
        check(all(0x6040 + 0x800 * a in objects for a in range(8)), "sdo list: the 8 axes' controlwords")
        read = run_json(sdo + ["read", "--iface", wire.if_a, "--slave", "0", "0x1018", "2", "--json"], ns=wire.ns_a)
        check(read["value"].split()[0] == str(slaves[0]["product_code"]), f"sdo read 0x1018:02: {read}")
        missing = run(sdo + ["read", "--iface", wire.if_a, "--slave", "0", "0x5555"], ns=wire.ns_a, check_rc=False)
        check(missing.returncode == 1 and "0x06020000" in missing.stderr and "does not exist" in missing.stderr,
              f"sdo read of a missing object: the abort with code and text, exit 1 ({missing.stderr.strip()})")
        refused = run(sdo + ["write", "--iface", wire.if_a, "--slave", "0", "0x1018", "1", "5"], ns=wire.ns_a,
                      check_rc=False)
        check(refused.returncode == 1 and "0x06010002" in refused.stderr and "read-only" in refused.stderr,
              f"sdo write to a read-only entry: the abort, exit 1 ({refused.stderr.strip()})")
        run(sdo + ["write", "--iface", wire.if_a, "--slave", "6", "0x6065", "0", "12345"], ns=wire.ns_a)
        back = run_json(sdo + ["read", "--iface", wire.if_a, "--slave", "6", "0x6065", "--json"], ns=wire.ns_a)
        check(back["value"].split()[0] == "12345", f"sdo write then read of the servo's following error window: {back}")

        # ---- run ---------------------------------------------------------
        result = run_json([binary(), "ecat", "run", "--iface", wire.if_a, "--cycle-us", "1000",
                           "--duration", "3", "--json"], ns=wire.ns_a, timeout=180)
        cycles = result["cycles"]
        check(cycles >= 1000, f"ran at least 1000 cycles at 1 kHz in 3 s: {cycles}")
        check(result["wkc_errors"] == 0, f"every returned frame had the expected WKC: {result['wkc_errors']} errors")
        check(result["lost_frames"] <= cycles // 100,
              f"lost frames stay under 1 % on a veth wire: {result['lost_frames']}")
        check(all(s["state"] == "OP" for s in result["slaves"]), "every slave was in OP at the end of the run")
        rtt = result["round_trip_us"]
        check(0 < rtt["min"] <= rtt["median"] <= rtt["p99"] <= rtt["max"], f"round-trip statistics are ordered: {rtt}")
        check("jitter_us" in result and result["jitter_us"]["max"] >= 0, "cycle jitter is reported")
        check(result.get("final_state") == "INIT" and result.get("problems") == [],
              f"the run ended cleanly in INIT: {result.get('final_state')} {result.get('problems')}")
        check(len(result["axes"]) == 17 and all(a["state"] != "fault" for a in result["axes"]),
              "17 axes (2 x 8 + 1 servo), none in fault")
        check(all(a["state"] == "switch on disabled" for a in result["axes"]),
              f"every axis was disabled before the segment left OP: {[a['state'] for a in result['axes']]}")
        # The master has stopped; give the slaves' process-data watchdogs
        # (100 ms) time to trip if the segment had been left in OP.
        time.sleep(0.5)
    finally:
        sim.stop()

    # ---- what the devices saw -------------------------------------------
    if not os.path.exists(report):
        fail(f"ecat sim wrote no report at {report}:\n{sim.output()}")
    with open(report) as f:
        devices = json.load(f)["slaves"]
    for pos, s in enumerate(result["slaves"]):
        dev = devices[pos]
        check(dev["last_outputs"] == s["outputs"],
              f"slave {pos}: the last outputs the master wrote reached the device ({s['outputs'][:16]}...)")
        check(dev["last_inputs"] != "" and int(dev["last_inputs"].replace(" ", ""), 16) != 0,
              f"slave {pos}: the device offered non-zero inputs")
        check(dev["last_inputs"] == s["inputs"], f"slave {pos}: the device's inputs came back to the master ({dev['last_inputs'][:24]} vs {s['inputs'][:24]})")
    # The master took the segment to INIT on exit: no watchdog tripped.
    for pos, dev in enumerate(devices):
        check(dev["al_state"] == "INIT" and dev["al_status_code"] == 0 and dev["watchdog_expirations"] == 0,
              f"slave {pos}: left in INIT without a watchdog trip ({dev['al_state']}, {dev['al_status_code']:#06x}, "
              f"{dev['watchdog_expirations']} expirations)")
        check(dev["outputs_safe"], f"slave {pos}: outputs are in their safe state")

# ---- the capture decodes in tshark ---------------------------------------
if shutil.which("tshark") is None:
    fail("tshark is not installed (scripts/setup installs it)")
malformed = run(["tshark", "-r", pcap, "-Y", "_ws.malformed || _ws.expert.severity >= error"]).stdout.strip()
check(malformed == "", f"tshark finds no malformed packets:\n{malformed[:2000]}")
fields = run(["tshark", "-r", pcap, "-T", "fields", "-e", "ecat.cmd"]).stdout.split()
names = {"1": "APRD", "2": "APWR", "3": "APRW", "4": "FPRD", "5": "FPWR", "7": "BRD", "8": "BWR",
         "12": "LRW", "13": "ARMW", "14": "FRMW"}
seen = set()
for field in fields:
    for value in field.split(","):
        value = value.strip()
        if value:
            seen.add(names.get(str(int(value, 0)), value))
print(f"datagram commands in the capture: {sorted(seen)}")
# scan (BRD count, APWR addresses), SII/registers (FPRD/FPWR), DC latch (BWR)
# and drift compensation (ARMW/FRMW), process data (LRW)
for cmd in ("BRD", "BWR", "APWR", "FPRD", "FPWR", "LRW", "FRMW"):
    check(cmd in seen, f"the capture holds {cmd} datagrams")


def field_values(field):
    out = set()
    for line in run(["tshark", "-r", pcap, "-T", "fields", "-e", field]).stdout.splitlines():
        out.update(v.strip() for v in line.split(",") if v.strip())
    return out


# SDO aborts travel as CoE service 2 (ETG.1000.6 §5.6.2.7.1): tshark shows their codes.
aborts = {int(v, 0) for v in field_values("ecat_mailbox.coe.abortcode")}
check({0x06020000, 0x06010002} <= aborts, f"tshark decodes the slaves' aborts with their codes: {sorted(map(hex, aborts))}")
opcodes = {int(v, 0) for v in field_values("ecat_mailbox.coe.sdoinfoopcode")}
check({1, 2, 3, 4, 5, 6} <= opcodes, f"tshark decodes SDO Information requests and responses: {sorted(opcodes)}")
names = field_values("ecat_mailbox.coe.sdoinfoname")
check({"Identity", "Vendor ID", "Device name"} <= names, f"tshark reads object and entry names: {sorted(names)[:12]}")
count = len(run(["tshark", "-r", pcap, "-T", "fields", "-e", "frame.number"]).stdout.split())
check(count > 2000, f"the capture holds the whole run ({count} frames)")
shutil.rmtree(work, ignore_errors=True)
