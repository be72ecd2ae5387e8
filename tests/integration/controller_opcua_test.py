"""The shop-floor controllers seen by node-opcua, each against the plant through its hardware face:
  - `smartfactory machine`: SCARA Robot 1's IPC masters its segment (EtherCAT in UDP on loopback);
  - `smartfactory gateway`: the gateways of conveyor 1, the box uploader and downloader and the
    legacy TOSHIBA robot poll their PLCs over Modbus TCP.
Each serves its machine model with the ontology's NodeSet2 (so the machine object is the line's
individual), a users file with one operator and anonymous viewers. node-opcua
(tests/peers/opcua/machine_model_client.mjs) browses Objects/Machines to it, reads its
Identification, PackML state and Tags (the axes; the PLC's registers as typed variables), is
refused Hold as a viewer, then as the operator calls Reset (the arm homes; the PLC's fault is
reset), Start, Hold, Unhold and Unhold again (BadInvalidState)
and sees the states in its subscription.
"""
import json
import os
import tempfile

from machine_model_peer import check_session, make_users, ontology_nodeset, run_peer
from sftest import Background, binary, check, wait_for, wait_for_line


# Each controller node-opcua drives: (command, machine, gateway kind or None, the ontology's individual,
# serial number, DeviceClass, tags that must read Good with their DataType).
CONTROLLERS = (
    ("machine", "scara-robot-1", None, "ScaraRobot1", "SR1-0001", "smart-robot",
     {"axis1.position": "Double", "axis4.statusword": "Int64", "io.vacuum_ok": "Boolean", "tool.z": "Double",
      "io.station_box": "Int64"}),
    ("gateway", "conveyor1", "conveyor", "Conveyor1", "S7-1200-C1", "conveyor",
     {"plc.motor_run": "Boolean", "plc.exit_eye": "Boolean", "plc.speed": "Int64", "plc.fault_code": "Int64"}),
    ("gateway", "uploader", "uploader", "Uploader", "FX5U-UP", "uploader",
     {"plc.box_type": "Int64", "plc.fault_code": "Int64", "plc.station_box": "Int64"}),
    ("gateway", "downloader", "downloader", "Downloader", "FX5U-DOWN", "downloader",
     {"plc.weight": "Double", "plc.candy_total": "Int64", "plc.station_box": "Int64"}),
    ("gateway", "toshiba", "legacy-robot", "Toshiba", "THL300-0042", "legacy-robot",
     {"robot.joint1": "Int64", "robot.tool_z": "Int64", "robot.fault_code": "Int64",
      "robot.station_box.toshiba": "Int64"}),
)


def controller_config(machine, kind, serial, tmp, endpoints, users, nodeset):
    """The YAML of a `machine` (kind None) or a `gateway` of `kind` for the plant's endpoints."""
    common = (f"dds: {{interface: lo, partition: controller-opcua-{os.getpid()}}}\n"
              f"opcua: {{port: 0, modes: none, users: {users}, anonymous: viewer, "
              f"pki: {os.path.join(tmp, 'pki')}, nodesets: [{nodeset}]}}\n")
    if kind is None:
        segment = [e["address"] for e in endpoints
                   if e["machine"] == machine and e["protocol"] == "ethercat-udp"][0]
        return f"machine: {machine}\nserial_number: {serial}\nethercat: {{link: 'udp:{segment}'}}\n" + common
    host, port = [e["address"] for e in endpoints if e["machine"] == machine][0].rsplit(":", 1)
    robot = "robot: {station: conveyor3/toshiba}\n" if kind == "legacy-robot" else ""
    return (f"machine: {machine}\nkind: {kind}\nserial_number: {serial}\n"
            f"modbus: {{host: {host}, port: {port}}}\n" + robot + common)


def drive(command, config, tmp, name):
    """Runs the controller process and lets node-opcua drive it; node-opcua's result."""
    process = Background([binary(), command, "--config", config, "--json"], log=config + ".log")
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
            for command, machine, kind, name, serial, device_class, tags in CONTROLLERS:
                config = os.path.join(tmp, machine + ".yaml")
                with open(config, "w") as f:
                    f.write(controller_config(machine, kind, serial, tmp, endpoints, users, nodeset))
                out = drive(command, config, tmp, name)
                check(out["identification"].get("SerialNumber") == serial
                      and out["identification"].get("DeviceClass") == device_class,
                      f"{name}'s Identification (OPC 40001-1): {out['identification']}")
                seen = {tag: (v["type"], v["status"]) for tag, v in out["tags"].items() if tag in tags}
                check(seen == {tag: (t, "Good") for tag, t in tags.items()},
                      f"{name}'s Tags read Good with their types: {seen} (of {sorted(out['tags'])})")
        finally:
            rc_plant = plant.stop()
        check(rc_plant == 0, f"the plant stops cleanly ({rc_plant})")


if __name__ == "__main__":
    main()
