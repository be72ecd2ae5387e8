"""The OPC UA model of a machine controller (libs/factory machine_model.hpp) seen by node-opcua.

machine_model_host serves a PackML test controller with serve_machine, as the `machine` and
`gateway` processes serve theirs: SecurityPolicy None, anonymous users are viewers, one operator
with a password (users file), and the ontology's NodeSet2 from `smartfactory kb to-nodeset`
loaded first, so the machine object is the ontology's individual ScaraRobot1.

node-opcua (tests/peers/opcua/machine_model_client.mjs) browses Objects/Machines to the machine,
reads its Identification and PackML state, is refused Hold as a viewer (BadUserAccessDenied),
then as the operator subscribes to Status.StateCurrent and calls Reset, Start, Hold, Unhold (each
followed by the state it leads to in the subscription) and Unhold again (BadInvalidState).
"""
import json
import os
import sys
import tempfile

from sftest import Background, binary, check, fail, node_peer, run, source_dir, wait_for_line

HOST = sys.argv[1]
ONTOLOGY = "http://smartfactory.example/ontology/candy"
STOPPED, IDLE, EXECUTE, HELD, RESETTING, STARTING, HOLDING, UNHOLDING = 2, 4, 6, 11, 15, 3, 10, 12


def sf(*args):
    return run([binary(), *args], timeout=120)


def make_users(tmp):
    users = os.path.join(tmp, "users.yaml")
    password = os.path.join(tmp, "olga.pw")
    with open(password, "w") as f:
        f.write("shift-lead\n")
    sf("opcua", "users", "add", users, "olga", "--role", "operator", "--password-file", password)
    return users


def main():
    peer = node_peer("opcua/machine_model_client.mjs")
    with tempfile.TemporaryDirectory(prefix="machine_model_") as tmp:
        nodeset = os.path.join(tmp, "candy.xml")
        root = source_dir()
        sf("kb", "to-nodeset", os.path.join(root, "ontology", "candy-factory.ttl"),
           os.path.join(root, "ontology", "prototype-line.ttl"), "-o", nodeset)
        host = Background([HOST, "--pki", os.path.join(tmp, "pki"), "--users", make_users(tmp),
                           "--anonymous", "viewer", "--nodeset", nodeset], log=os.path.join(tmp, "host.log"))
        try:
            url = wait_for_line(host, "listening on ", 30).split()[-1]
            proc = run(peer + [url, "--user", "olga=shift-lead"], timeout=180)
            lines = [line for line in proc.stdout.splitlines() if line.startswith("{")]
            if not lines:
                fail(f"node-opcua printed no result:\n{proc.stdout}\n{proc.stderr}")
            out = json.loads(lines[-1])
        finally:
            rc = host.stop()
        print(json.dumps(out, indent=1))
        check(out["errors"] == [], f"every node-opcua step succeeded: {out['errors']}\n{host.output()[-3000:]}")
        check(out["machines"] == [{"name": "ScaraRobot1", "namespace": ONTOLOGY}],
              f"Objects/Machines holds the ontology's individual ScaraRobot1: {out['machines']}")
        for child in ("Identification", "PackML", "Job", "Tags", "Fault", "manufacturer", "model"):
            check(child in out["machineChildren"], f"the machine has {child}: {out['machineChildren']}")
        check(out["identification"] == {"Manufacturer": "smartfactory", "Model": "SCARA Robot 1",
                                        "SerialNumber": "SR1-0001", "DeviceClass": "smart-robot"},
              f"Identification (OPC 40001-1): {out['identification']}")
        check(out["stateBefore"] == STOPPED, f"StateCurrent reads Stopped (2): {out['stateBefore']}")
        check(out["viewerHold"] == "BadUserAccessDenied", f"a viewer's Hold: {out['viewerHold']}")
        calls = [(c["method"], c["status"]) for c in out["calls"]]
        check(calls == [("Reset", "Good"), ("Start", "Good"), ("Hold", "Good"), ("Unhold", "Good"),
                        ("Unhold", "BadInvalidState")], f"the operator's calls: {calls}")
        # The subscription saw the states in order (acting states may pass between two samples).
        settled = [s for s in out["states"] if s not in (RESETTING, STARTING, HOLDING, UNHOLDING)]
        dedup = [s for i, s in enumerate(settled) if i == 0 or settled[i - 1] != s]
        check(dedup == [STOPPED, IDLE, EXECUTE, HELD, EXECUTE], f"StateCurrent notifications: {out['states']}")
        check(rc == 0, f"machine_model_host stops cleanly on SIGTERM (exit {rc})")


if __name__ == "__main__":
    main()
