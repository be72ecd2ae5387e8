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

from machine_model_peer import check_session, make_users, ontology_nodeset, run_peer
from sftest import Background, binary, check, wait_for, wait_for_line


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


def drive(command, config, tmp, name):
    """Runs the controller process and lets node-opcua drive it; node-opcua's result."""
    process = Background([binary(), command, "--config", config, "--json"], log=os.path.join(tmp, command + ".log"))
    try:
        def ready():
            for line in process.output().splitlines():
                if line.startswith("{") and json.loads(line).get("event") == "ready":
                    return json.loads(line)
            return None

        wait_for(ready, 60, f"{command} to be ready")
        out = run_peer(ready()["opcua"])
    finally:
        rc = process.stop()
    check_session(out, name, process.output())
    check(rc == 0, f"{command} stops cleanly on SIGTERM (exit {rc})")
    return out


def main():
    with tempfile.TemporaryDirectory(prefix="controller_opcua_") as tmp:
        nodeset = ontology_nodeset(tmp)
        users = make_users(tmp)
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
                out = drive(command, config, tmp, name)
                check(out["identification"].get("SerialNumber") == serial
                      and out["identification"].get("DeviceClass") == device_class,
                      f"Identification (OPC 40001-1): {out['identification']}")
        finally:
            rc_plant = plant.stop()
        check(rc_plant == 0, f"the plant stops cleanly ({rc_plant})")


if __name__ == "__main__":
    main()
