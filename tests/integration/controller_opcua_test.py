"""The shop-floor controllers seen by node-opcua, each against the plant through its hardware face:
  - `smartfactory machine`: SCARA Robot 1's IPC masters its segment (EtherCAT in UDP on loopback);
  - `smartfactory gateway`: conveyor 1's gateway polls its PLC over Modbus TCP.
Each serves its machine model with the ontology's NodeSet2 (so the machine object is the line's
individual), a users file with one operator and anonymous viewers. node-opcua
(tests/peers/opcua/machine_model_client.mjs) browses Objects/Machines to it, reads its
Identification and PackML state, is refused Hold as a viewer, then as the operator calls Reset
(the arm homes; the PLC's fault is reset), Start, Hold, Unhold and Unhold again (BadInvalidState)
and sees the states in its subscription.
"""
import json
import os
import tempfile

from sftest import Background, binary, check, fail, node_peer, run, source_dir, wait_for, wait_for_line

ONTOLOGY = "http://smartfactory.example/ontology/candy"
STOPPED, IDLE, EXECUTE, HELD, RESETTING, STARTING, HOLDING, UNHOLDING = 2, 4, 6, 11, 15, 3, 10, 12


def sf(*args):
    return run([binary(), *args], timeout=120)


def controller_config(kind, tmp, endpoints, users, nodeset):
    """The YAML of a `machine` (kind None) or a conveyor1 `gateway` for the plant's endpoints."""
    common = (f"dds: {{interface: lo, partition: controller-opcua-{os.getpid()}}}\n"
              f"opcua: {{port: 0, modes: none, users: {users}, anonymous: viewer, "
              f"pki: {os.path.join(tmp, 'pki')}, nodesets: [{nodeset}]}}\n")
    if kind is None:
        segment = [e["address"] for e in endpoints
                   if e["machine"] == "scara-robot-1" and e["protocol"] == "ethercat-udp"][0]
        return (f"machine: scara-robot-1\nserial_number: SR1-0001\nethercat: {{link: 'udp:{segment}'}}\n"
                + common)
    host, port = [e["address"] for e in endpoints if e["machine"] == "conveyor1"][0].rsplit(":", 1)
    return (f"machine: conveyor1\nkind: conveyor\nserial_number: S7-1200-C1\n"
            f"modbus: {{host: {host}, port: {port}}}\n" + common)


def drive(command, config, tmp, peer):
    """Runs the controller process, lets node-opcua drive it; node-opcua's result and the exit code."""
    process = Background([binary(), command, "--config", config, "--json"], log=os.path.join(tmp, command + ".log"))
    try:
        def ready():
            for line in process.output().splitlines():
                if line.startswith("{") and json.loads(line).get("event") == "ready":
                    return json.loads(line)
            return None

        wait_for(ready, 60, f"{command} to be ready")
        proc = run(peer + [ready()["opcua"], "--user", "olga=shift-lead"], timeout=180)
        lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
        if not lines:
            fail(f"node-opcua printed no result:\n{proc.stdout}\n{proc.stderr}")
        out = json.loads(lines[-1])
    finally:
        rc = process.stop()
    print(json.dumps(out, indent=1))
    check(out["errors"] == [], f"every node-opcua step succeeded: {out['errors']}\n{process.output()[-3000:]}")
    check(rc == 0, f"{command} stops cleanly on SIGTERM (exit {rc})")
    return out


def check_drive(out, name, serial, device_class):
    check(out["machines"] == [{"name": name, "namespace": ONTOLOGY}],
          f"Objects/Machines holds the ontology's individual {name}: {out['machines']}")
    check(out["identification"].get("SerialNumber") == serial
          and out["identification"].get("DeviceClass") == device_class,
          f"Identification (OPC 40001-1): {out['identification']}")
    check(out["stateBefore"] == STOPPED, f"StateCurrent reads Stopped (2): {out['stateBefore']}")
    check(out["viewerHold"] == "BadUserAccessDenied", f"a viewer's Hold: {out['viewerHold']}")
    calls = [(c["method"], c["status"]) for c in out["calls"]]
    check(calls == [("Reset", "Good"), ("Start", "Good"), ("Hold", "Good"), ("Unhold", "Good"),
                    ("Unhold", "BadInvalidState")], f"the operator's calls: {calls}")
    settled = [s for s in out["states"] if s not in (RESETTING, STARTING, HOLDING, UNHOLDING)]
    dedup = [s for i, s in enumerate(settled) if i == 0 or settled[i - 1] != s]
    check(dedup == [STOPPED, IDLE, EXECUTE, HELD, EXECUTE], f"StateCurrent notifications: {out['states']}")


def main():
    peer = node_peer("opcua/machine_model_client.mjs")
    with tempfile.TemporaryDirectory(prefix="controller_opcua_") as tmp:
        root = source_dir()
        nodeset = os.path.join(tmp, "candy.xml")
        sf("kb", "to-nodeset", os.path.join(root, "ontology", "candy-factory.ttl"),
           os.path.join(root, "ontology", "prototype-line.ttl"), "-o", nodeset)
        users = os.path.join(tmp, "users.yaml")
        with open(os.path.join(tmp, "olga.pw"), "w") as f:
            f.write("shift-lead\n")
        sf("opcua", "users", "add", users, "olga", "--role", "operator", "--password-file",
           os.path.join(tmp, "olga.pw"))
        plant = Background([binary(), "plant", "--json", "--ecat-port", "0", "--status-interval", "0"],
                           log=os.path.join(tmp, "plant.log"))
        try:
            endpoints = json.loads(wait_for_line(plant, '{"endpoints"', 20))["endpoints"]
            for command, kind, name, serial, device_class in (
                    ("machine", None, "ScaraRobot1", "SR1-0001", "smart-robot"),
                    ("gateway", "conveyor", "Conveyor1", "S7-1200-C1", "conveyor")):
                config = os.path.join(tmp, command + ".yaml")
                with open(config, "w") as f:
                    f.write(controller_config(kind, tmp, endpoints, users, nodeset))
                check_drive(drive(command, config, tmp, peer), name, serial, device_class)
        finally:
            rc_plant = plant.stop()
        check(rc_plant == 0, f"the plant stops cleanly ({rc_plant})")


if __name__ == "__main__":
    main()
