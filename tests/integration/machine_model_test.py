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
import os
import sys
import tempfile

from machine_model_peer import check_session, make_users, ontology_nodeset, run_peer
from sftest import Background, check, wait_for_line

HOST = sys.argv[1]


def main():
    with tempfile.TemporaryDirectory(prefix="machine_model_") as tmp:
        host = Background([HOST, "--pki", os.path.join(tmp, "pki"), "--users", make_users(tmp),
                           "--anonymous", "viewer", "--nodeset", ontology_nodeset(tmp)],
                          log=os.path.join(tmp, "host.log"))
        try:
            out = run_peer(wait_for_line(host, "listening on ", 30).split()[-1])
        finally:
            rc = host.stop()
        check_session(out, "ScaraRobot1", host.output())
        for child in ("Identification", "PackML", "Job", "Tags", "Fault", "manufacturer", "model"):
            check(child in out["machineChildren"], f"the machine has {child}: {out['machineChildren']}")
        check(out["identification"] == {"Manufacturer": "smartfactory", "Model": "SCARA Robot 1",
                                        "SerialNumber": "SR1-0001", "DeviceClass": "smart-robot"},
              f"Identification (OPC 40001-1): {out['identification']}")
        check(rc == 0, f"machine_model_host stops cleanly on SIGTERM (exit {rc})")


if __name__ == "__main__":
    main()
