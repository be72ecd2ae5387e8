"""The smart robot's IPC seen by node-opcua: `smartfactory plant` serves SCARA Robot 1's segment
(EtherCAT in UDP on loopback), `smartfactory machine` masters it and serves its machine model with
the ontology's NodeSet2 (so the machine object is the individual ScaraRobot1), a users file with
one operator and anonymous viewers. node-opcua (tests/peers/opcua/machine_model_client.mjs)
browses Objects/Machines to it, reads its Identification and PackML state, is refused Hold as a
viewer, then as the operator calls Reset (the real arm homes), Start, Hold, Unhold and Unhold again
(BadInvalidState) and sees the states in its subscription.
"""
import json
import os
import tempfile

from sftest import Background, binary, check, fail, node_peer, run, source_dir, wait_for, wait_for_line

ONTOLOGY = "http://smartfactory.example/ontology/candy"
STOPPED, IDLE, EXECUTE, HELD, RESETTING, STARTING, HOLDING, UNHOLDING = 2, 4, 6, 11, 15, 3, 10, 12


def sf(*args):
    return run([binary(), *args], timeout=120)


def main():
    peer = node_peer("opcua/machine_model_client.mjs")
    with tempfile.TemporaryDirectory(prefix="machine_opcua_") as tmp:
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
        machine = None
        try:
            endpoints = json.loads(wait_for_line(plant, '{"endpoints"', 20))["endpoints"]
            segment = [e["address"] for e in endpoints
                       if e["machine"] == "scara-robot-1" and e["protocol"] == "ethercat-udp"][0]
            config = os.path.join(tmp, "machine.yaml")
            with open(config, "w") as f:
                f.write(f"machine: scara-robot-1\nserial_number: SR1-0001\nethercat: {{link: 'udp:{segment}'}}\n"
                        f"dds: {{interface: lo, partition: machine-opcua-{os.getpid()}}}\n"
                        f"opcua: {{port: 0, modes: none, users: {users}, anonymous: viewer, "
                        f"pki: {os.path.join(tmp, 'pki')}, nodesets: [{nodeset}]}}\n")
            machine = Background([binary(), "machine", "--config", config, "--json"],
                                 log=os.path.join(tmp, "machine.log"))

            def ready():
                for line in machine.output().splitlines():
                    if line.startswith("{") and json.loads(line).get("event") == "ready":
                        return json.loads(line)
                return None

            wait_for(ready, 60, "the machine to be ready")
            url = ready()["opcua"]
            proc = run(peer + [url, "--user", "olga=shift-lead"], timeout=180)
            lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
            if not lines:
                fail(f"node-opcua printed no result:\n{proc.stdout}\n{proc.stderr}")
            out = json.loads(lines[-1])
        finally:
            rc_machine = machine.stop() if machine else 0
            rc_plant = plant.stop()
        print(json.dumps(out, indent=1))
        check(out["errors"] == [], f"every node-opcua step succeeded: {out['errors']}\n{machine.output()[-3000:]}")
        check(out["machines"] == [{"name": "ScaraRobot1", "namespace": ONTOLOGY}],
              f"Objects/Machines holds the ontology's individual ScaraRobot1: {out['machines']}")
        check(out["identification"].get("SerialNumber") == "SR1-0001"
              and out["identification"].get("DeviceClass") == "smart-robot",
              f"Identification (OPC 40001-1): {out['identification']}")
        check(out["stateBefore"] == STOPPED, f"StateCurrent reads Stopped (2): {out['stateBefore']}")
        check(out["viewerHold"] == "BadUserAccessDenied", f"a viewer's Hold: {out['viewerHold']}")
        calls = [(c["method"], c["status"]) for c in out["calls"]]
        check(calls == [("Reset", "Good"), ("Start", "Good"), ("Hold", "Good"), ("Unhold", "Good"),
                        ("Unhold", "BadInvalidState")], f"the operator's calls: {calls}")
        settled = [s for s in out["states"] if s not in (RESETTING, STARTING, HOLDING, UNHOLDING)]
        dedup = [s for i, s in enumerate(settled) if i == 0 or settled[i - 1] != s]
        check(dedup == [STOPPED, IDLE, EXECUTE, HELD, EXECUTE], f"StateCurrent notifications: {out['states']}")
        check(rc_machine == 0 and rc_plant == 0, f"machine and plant stop cleanly ({rc_machine}, {rc_plant})")


if __name__ == "__main__":
    main()
