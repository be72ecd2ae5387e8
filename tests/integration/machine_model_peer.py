"""What the tests that let node-opcua drive a machine controller's OPC UA model share
(tests/peers/opcua/machine_model_client.mjs): the ontology's NodeSet2, a users file with the
operator olga, running the peer, and the checks of the session it reports."""
import json
import os

from sftest import binary, check, node_peer_result, run, source_dir

ONTOLOGY = "http://smartfactory.example/ontology/candy"
STOPPED, IDLE, EXECUTE, HELD, RESETTING, STARTING, HOLDING, UNHOLDING = 2, 4, 6, 11, 15, 3, 10, 12


def sf(*args):
    return run([binary(), *args], timeout=120)


def ontology_nodeset(tmp):
    """The ontology and the line's individuals as `kb to-nodeset` makes them."""
    nodeset = os.path.join(tmp, "candy.xml")
    root = source_dir()
    sf("kb", "to-nodeset", os.path.join(root, "ontology", "candy-factory.ttl"),
       os.path.join(root, "ontology", "prototype-line.ttl"), "-o", nodeset)
    return nodeset


def make_users(tmp):
    """A users file with one operator, olga (password shift-lead)."""
    users = os.path.join(tmp, "users.yaml")
    password = os.path.join(tmp, "olga.pw")
    with open(password, "w") as f:
        f.write("shift-lead\n")
    sf("opcua", "users", "add", users, "olga", "--role", "operator", "--password-file", password)
    return users


def run_peer(url):
    """node-opcua against `url` as an anonymous viewer and as olga; its JSON result."""
    return node_peer_result("opcua/machine_model_client.mjs", [url, "--user", "olga=shift-lead"], timeout=180)


def check_session(out, name, log=""):
    """The machine `name` found as the ontology's individual, a viewer refused Hold, the operator's
    Reset, Start, Hold, Unhold and Unhold again, and the states the subscription saw."""
    print(json.dumps(out, indent=1))
    check(out["errors"] == [], f"every node-opcua step succeeded: {out['errors']}\n{log[-3000:]}")
    check(out["machines"] == [{"name": name, "namespace": ONTOLOGY}],
          f"Objects/Machines holds the ontology's individual {name}: {out['machines']}")
    check(out["stateBefore"] == STOPPED, f"StateCurrent reads Stopped (2): {out['stateBefore']}")
    check(out["viewerHold"] == "BadUserAccessDenied", f"a viewer's Hold: {out['viewerHold']}")
    calls = [(c["method"], c["status"]) for c in out["calls"]]
    check(calls == [("Reset", "Good"), ("Start", "Good"), ("Hold", "Good"), ("Unhold", "Good"),
                    ("Unhold", "BadInvalidState")], f"the operator's calls: {calls}")
    # The subscription saw the states in order (acting states may pass between two samples).
    settled = [s for s in out["states"] if s not in (RESETTING, STARTING, HOLDING, UNHOLDING)]
    dedup = [s for i, s in enumerate(settled) if i == 0 or settled[i - 1] != s]
    check(dedup == [STOPPED, IDLE, EXECUTE, HELD, EXECUTE], f"StateCurrent notifications: {out['states']}")
